// The set-up of Lloyd's method: sites per component, input checks, operators
// (pipelines/src/voronoi/cvt_lloyd_setup.hpp; thesis §3.7.1, §3.3).
#include "cvt_lloyd_setup.hpp"
#include "locus/core/host_allocator.hpp"

#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/mesh/lifted_metric.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/site_neighborhoods.hpp"

namespace locus {

namespace {

// Face f's first vertex; of a triangle mesh from f0 (the cvt command lends the
// mesh's face_vertices out during Lloyd).
int32_t face_first_vertex(const Mesh& m, int32_t f) {
  return m.is_triangle_mesh() ? m.f0[f] : m.face_vertices[static_cast<size_t>(m.face_offsets[f])];
}

// Heat never crosses components: a component without a site would have no
// cell (and labels of -1). Sites stay in their cell's component, so checking
// the initial sites is enough.
void check_components_have_sites(const Mesh& m, const MeshDerived& d, std::span<const SurfacePoint> sites) {
  const int32_t n = m.num_vertices();
  const HostVector<int32_t>& comp = d.component;
  const int32_t nc = d.components;
  if (nc <= 1) return;
  std::vector<uint8_t> has_site(static_cast<size_t>(nc), 0);
  for (const SurfacePoint& p : sites) {
    const int32_t v = p.vertex >= 0 ? p.vertex : face_first_vertex(m, p.face);
    has_site[static_cast<size_t>(comp[v])] = 1;
  }
  for (int32_t v = 0; v < n; ++v)
    if (comp[v] >= 0 && !has_site[static_cast<size_t>(comp[v])])
      fail(ErrorCode::BadInput, "cvt: the connected component containing vertex " + std::to_string(v) +
                                    " has no site (the mesh has " + std::to_string(nc) +
                                    " components; every component needs at least one site)");
}

}  // namespace

void give_every_component_a_site(const Mesh& m, const MeshDerived* given, std::vector<SurfacePoint>& sites) {
  std::vector<int32_t> own;
  const int32_t nc = given ? given->components : connected_components(m, own);
  if (nc <= 1) return;
  const int32_t* comp = given ? given->component.data() : own.data();
  if (static_cast<int32_t>(sites.size()) < nc)
    fail(ErrorCode::BadUsage, "cvt: " + std::to_string(sites.size()) + " sites for " + std::to_string(nc) +
                                  " connected components; every component needs at least one site");
  auto comp_of = [&](const SurfacePoint& p) {
    return comp[p.vertex >= 0 ? p.vertex : face_first_vertex(m, p.face)];
  };
  std::vector<int32_t> count(nc, 0), first_vertex(nc, -1);
  for (const SurfacePoint& p : sites) ++count[comp_of(p)];
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (comp[v] >= 0 && first_vertex[comp[v]] < 0) first_vertex[comp[v]] = v;
  for (int32_t c = 0; c < nc; ++c) {
    if (count[c] > 0) continue;
    const int32_t donor = static_cast<int32_t>(std::max_element(count.begin(), count.end()) - count.begin());
    for (size_t i = sites.size(); i-- > 0;)
      if (comp_of(sites[i]) == donor) {
        sites[i] = vertex_point(first_vertex[c]);
        break;
      }
    --count[donor];
    ++count[c];
  }
}

const MeshDerived& check_lloyd_input(const Mesh& m, const MeshDerived* given, std::span<const SurfacePoint> sites,
                                     const LloydOptions& opt, MeshDerived& own) {
  const int32_t ns = static_cast<int32_t>(sites.size());
  if (ns < 1) fail(ErrorCode::BadUsage, "cvt: at least one site");
  if (opt.iterations < 0) fail(ErrorCode::BadUsage, "cvt: negative iteration count");
  if (opt.graph_iterations < -1) fail(ErrorCode::BadUsage, "cvt: graph_iterations must be >= 0 (or -1: automatic)");
  if (!(opt.stop_energy >= 0) || !std::isfinite(opt.stop_energy))
    fail(ErrorCode::BadUsage, "cvt: stop_energy must be a finite number >= 0");
  if (!(opt.anisotropy >= 0) || !std::isfinite(opt.anisotropy))
    fail(ErrorCode::BadUsage, "cvt: the anisotropy must be a finite number >= 0");
  if (!(opt.init_radius > 0)) fail(ErrorCode::BadUsage, "cvt: init_radius must be positive");
  if (opt.fit_rings < 1 || opt.fit_rings > 4) fail(ErrorCode::BadUsage, "cvt: fit_rings must be 1 to 4");
  if (!(opt.fit_sigma >= 0) || !std::isfinite(opt.fit_sigma))
    fail(ErrorCode::BadUsage, "cvt: fit_sigma must be a finite number >= 0");
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  if (!given || !requirements_checked(*given, req)) check_requirements(m, req);
  if (given) check_derived_of(*given, m, "cvt");
  if (!given) own = derive_mesh(m);
  const MeshDerived& derived = given ? *given : own;
  for (int32_t s = 0; s < ns; ++s) check_surface_point(m, sites[s], "site", s);
  check_components_have_sites(m, derived, sites);
  return derived;
}

void prepare_lloyd_operators(const Mesh& m, const MeshDerived& d, const LloydOptions& opt, HostVector<double>& area_r3,
                             BatchStopwatch& sw, const RunContext& ctx, LloydOperators& ops) {
  const int32_t n = m.num_vertices();
  // Operator of the metric (R^3, or the R^6 lift) for time t: A = M - t L, lumped mass, h.
  std::vector<double> lifted;
  if (opt.anisotropy > 0) lifted = lifted_positions(m, opt.anisotropy);
  auto build = [&](double t, HostVector<double>& mass, double& h) {
    if (opt.anisotropy > 0) return heat_operator_from_positions(m, lifted, 6, t, mass, h);
    mass.assign(d.mass.begin(), d.mass.end());
    h = d.h;
    return heat_operator(m, t);
  };
  if (!(opt.t_abs >= 0) || !std::isfinite(opt.t_abs) ||
      (opt.t_abs == 0 && (!(opt.t_factor > 0) || !std::isfinite(opt.t_factor))))
    fail(ErrorCode::BadUsage, "cvt: the diffusion time must be a finite positive number");
  if (!(opt.t_centroid_factor >= 0) || !std::isfinite(opt.t_centroid_factor) || !(opt.t_centroid_abs >= 0) ||
      !std::isfinite(opt.t_centroid_abs))
    fail(ErrorCode::BadUsage, "cvt: the centroid diffusion time must be a finite number >= 0");
  if (opt.prepared) {
    if (opt.anisotropy > 0) fail(ErrorCode::BadUsage, "cvt: a prepared operator is for isotropic CVT only");
    const size_t masses = opt.prepared->mass.empty() ? d.mass.size() : opt.prepared->mass.size();
    if (opt.prepared->n != n || masses != static_cast<size_t>(n))
      fail(ErrorCode::BadUsage, "cvt: the prepared operator belongs to another mesh");
    ops.area_op = std::move(area_r3);
  } else {
    HostVector<double> mass;
    double h = 0;
    if (opt.anisotropy > 0) {
      heat_operator_from_positions(m, lifted, 6, 1.0, mass, h);  // h of the lifted metric first
    } else {
      h = d.h;
    }
    const double t = opt.t_abs > 0 ? opt.t_abs : opt.t_factor * h * h;
    const CscMatrix A = build(t, mass, h);
    if (opt.anisotropy > 0)
      ops.area_op = face_areas_from_positions(m, lifted, 6);
    else
      ops.area_op = std::move(area_r3);
    const double op_s = sw.lap();
    ops.H_own = prepare_heat_diffusion(A, std::move(mass), h, t, ctx);
    ops.H_own.operator_s = op_s;
  }
  ops.H = opt.prepared ? opt.prepared : &ops.H_own;
  const HeatDiffusion& H = *ops.H;
  // Centroids with their own diffusion time: same pattern, so the symbolic factor is shared.
  HeatDiffusion& Hc_own = ops.Hc_own;
  const double t_centroid = opt.t_centroid_abs > 0 ? opt.t_centroid_abs : opt.t_centroid_factor * H.h * H.h;
  if (t_centroid > 0) {
    sw.lap();
    Hc_own.n = H.n;
    Hc_own.h = H.h;
    Hc_own.t = t_centroid;
    double h = 0;
    const CscMatrix A = build(Hc_own.t, Hc_own.mass, h);
    Hc_own.factor = factorize(H.factor.symbolic, A, ctx);
    Hc_own.factor_s = sw.lap();
  }
  ops.Hc = t_centroid > 0 ? &Hc_own : ops.H;
  const HostVector<double>& mass_c = ops.Hc->mass.empty() ? d.mass : ops.Hc->mass;
  ops.mass_c = std::span<const double>(mass_c.data(), mass_c.size());
}

int32_t graph_iterations_of(const LloydOptions& opt, int32_t vertices) {
  if (opt.graph_iterations >= 0) return std::min(opt.graph_iterations, opt.iterations);
  return vertices >= kGraphLloydVertices ? std::max(0, opt.iterations - kLargeHeatIterations) : 0;
}

void geometry_beside_graph_start(const Mesh& m, const MeshDerived& d, HostVector<double>&& area_op,
                                 int32_t graph_iterations, ProgressTicker& ticker, const RunContext& ctx,
                                 std::vector<SurfacePoint>& sites, CentroidGeometry& geo, VertexStars& stars,
                                 HostVector<int32_t>& first) {
  tbb::task_group graph;
  if (graph_iterations > 0)
    graph.run([&] { first = geodesic_lloyd(m, d.adjacency, d.mass, sites, graph_iterations, ctx); });
  try {
    geo = prepare_centroid_geometry(m, d.adjacency);
    ticker.add(1.0);
    stars = vertex_stars(m, geo.vf_offsets, geo.vf_faces, std::move(area_op));  // the fits' face lists, borrowed
    ticker.add(1.0);
  } catch (...) {
    try {  // the task reads what unwinding frees: wait for it first
      graph.wait();
    } catch (...) {
    }
    throw;
  }
  graph.wait();
}

}  // namespace locus
