// The C API's diffusion calls (locus.h): CVT and remeshing, heat values,
// operator preparation, random points, Voronoi diagrams, natural-neighbor
// coordinates, skinning weights (the one-call form; the skinweights command is
// c_api_skinning_command.cpp), ADF/HKS and heat exchange.
#include "c_api_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace locus::c_api_detail;

namespace {

// The arguments locus_cvt_ex and locus_cvt_remesh share.
// The sites are checked by the Session (the cvt command's checks); the C API's own
// contract bounds the iterations and keeps cvt's time.
void check_cvt_call(int32_t iters, const CallContext& cc) {
  if (iters < 0 || iters > kMaxIterations)
    fail(ErrorCode::BadUsage, "iters = " + std::to_string(iters) + " is not in 0.." + std::to_string(kMaxIterations));
  if (cc.t_factor != 0.0)
    fail(ErrorCode::BadUsage, "t_factor: cvt uses its own default t = 4h^2; leave t_factor at 0 (default)");
}

}  // namespace

extern "C" {

locus_status locus_cvt_ex(locus_session* session, int32_t sites, int32_t iters, uint64_t seed,
                          int32_t* out_labels_nv, double* out_sites_xyz, const locus_run_options* opts) {
  return session_run("locus_cvt", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out_labels_nv != nullptr, "out_labels_nv is NULL");
    check_cvt_call(iters, cc);
    const locus::CvtResult r = s.cvt(sites, iters, seed, cc.ctx);
    // The caller's arrays hold `sites` sites: a mesh that needed another count
    // (one site per connected component, or its manifold sheets' repair) is refused.
    const size_t used = r.site_xyz.size() / 3;
    if (used != static_cast<size_t>(sites))
      fail(ErrorCode::BadInput, "the mesh needs " + std::to_string(used) + " sites, not " + std::to_string(sites) +
                                    " (one per connected component at least): call again with sites = " +
                                    std::to_string(used));
    std::copy(r.label.begin(), r.label.end(), out_labels_nv);
    if (out_sites_xyz) std::copy(r.site_xyz.begin(), r.site_xyz.end(), out_sites_xyz);
  });
}

locus_status locus_cvt(locus_session* session, int32_t sites, int32_t iters, uint64_t seed, int32_t* out_labels_nv) {
  return locus_cvt_ex(session, sites, iters, seed, out_labels_nv, nullptr, nullptr);
}

}  // extern "C"

extern "C" {

locus_status locus_cvt_remesh(locus_session* session, int32_t sites, int32_t iters, uint64_t seed,
                              const locus_run_options* opts, locus_remesh** out) {
  return session_run("locus_cvt_remesh", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out != nullptr, "out is NULL");
    check_cvt_call(iters, cc);
    auto h = std::make_unique<locus_remesh>();
    h->r = s.cvt(sites, iters, seed, cc.ctx, true);
    if (!h->r.remeshed)
      fail(ErrorCode::Numerical, "the cells still break the closed-ball property after the repair rounds; "
                                 "no manifold remesh (try more sites)");
    *out = h.release();
  });
}

locus_status locus_remesh_get(const locus_remesh* remesh, double* out_xyz, int32_t* out_tris) {
  return guarded("locus_remesh_get", [&] {
    require(remesh != nullptr, "remesh is NULL");
    if (out_xyz) std::copy(remesh->r.remesh_xyz.begin(), remesh->r.remesh_xyz.end(), out_xyz);
    if (out_tris) std::copy(remesh->r.remesh_triangles.begin(), remesh->r.remesh_triangles.end(), out_tris);
  });
}

locus_status locus_remesh_get_stats(const locus_remesh* remesh, locus_remesh_stats* out) {
  return guarded("locus_remesh_get_stats", [&] {
    require(remesh != nullptr, "remesh is NULL");
    require(out != nullptr, "out is NULL");
    const locus::CvtResult& r = remesh->r;
    *out = locus_remesh_stats{};
    out->vertices = static_cast<int64_t>(r.remesh_xyz.size() / 3);
    out->faces = static_cast<int64_t>(r.remesh_triangles.size() / 3);
    out->manifold = r.remeshed ? 1 : 0;
    out->genus = r.remesh_genus;
    out->components = r.remesh_components;
    out->boundary_loops = r.remesh_boundary_loops;
    out->mean_min_angle_deg = r.mean_min_angle_deg;
    out->min_angle_deg = r.min_angle_deg;
    out->pct_below_30_deg = r.pct_below_30_deg;
    out->hausdorff_rel = r.hausdorff_rel;
    out->added_sites = r.added_sites;
  });
}

void locus_remesh_destroy(locus_remesh* remesh) { delete remesh; }

locus_status locus_heat_values(locus_session* session, const int64_t* sources, int64_t n_sources,
                               const int64_t* targets, int64_t n_targets, double* out,
                               const locus_run_options* opts) {
  return session_run("locus_heat_values", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(sources != nullptr, "sources is NULL");
    require(targets != nullptr, "targets is NULL");
    require(out != nullptr, "out is NULL");
    if (n_sources < 1 || n_targets < 1 || n_sources > kMaxHeatValues || n_targets > kMaxHeatValues ||
        n_sources * n_targets > kMaxHeatValues)
      fail(ErrorCode::BadUsage, "n_sources = " + std::to_string(n_sources) + ", n_targets = " +
                                    std::to_string(n_targets) + ": each must be >= 1 and their product <= 2^28");
    std::vector<int32_t> src(static_cast<size_t>(n_sources)), tgt(static_cast<size_t>(n_targets));
    for (int64_t k = 0; k < n_sources; ++k)
      src[k] = vertex_id(s, sources[k], ("sources[" + std::to_string(k) + "] =").c_str());
    for (int64_t k = 0; k < n_targets; ++k)
      tgt[k] = vertex_id(s, targets[k], ("targets[" + std::to_string(k) + "] =").c_str());
    const std::vector<double> v = s.heat_values(src, tgt, cc.heat(), cc.ctx);
    std::copy(v.begin(), v.end(), out);
  });
}

}  // extern "C"

struct locus_nncoords_field {
  explicit locus_nncoords_field(locus::NaturalNeighbors f, int32_t nv, int32_t nf) : field(std::move(f)), nv(nv), nf(nf) {}
  locus::NaturalNeighbors field;
  int32_t nv, nf;
};

extern "C" {

locus_status locus_session_prepare(locus_session* session, int32_t operators, const locus_run_options* opts) {
  return session_run("locus_session_prepare", session, opts, [&](locus::Session& s, CallContext& cc) {
    const int32_t all = LOCUS_PREPARE_HEAT_METHOD | LOCUS_PREPARE_DIFFUSION | LOCUS_PREPARE_LAPLACIAN;
    if (operators & ~all)
      fail(ErrorCode::BadUsage, "operators = " + std::to_string(operators) + " has bits outside LOCUS_PREPARE_*");
    if (operators & LOCUS_PREPARE_HEAT_METHOD) s.prepare_heat(cc.heat(), cc.ctx);
    if (operators & LOCUS_PREPARE_DIFFUSION) s.prepare_diffusion(cc.heat(), cc.ctx);
    if (operators & LOCUS_PREPARE_LAPLACIAN) s.prepare_patch_parameterization(cc.ctx);
  });
}

locus_status locus_random_surface_points(const locus_session* session, int64_t count, uint64_t seed,
                                         locus_surface_point* out) {
  return guarded("locus_random_surface_points", [&] {
    require(session != nullptr, "session is NULL");
    require(out != nullptr, "out is NULL");
    if (count < 0 || count > kMaxVertices)
      fail(ErrorCode::BadUsage, "count = " + std::to_string(count) + " is not in 0.." + std::to_string(kMaxVertices));
    const std::vector<locus::MeshPoint> p = session->session.random_points(static_cast<int32_t>(count), seed);
    for (size_t k = 0; k < p.size(); ++k) out[k] = locus_surface_point{p[k].face, -1, {p[k].bary[0], p[k].bary[1], p[k].bary[2]}};
  });
}

locus_status locus_voronoi_bound(const locus_session* session, int64_t* max_points, int64_t* max_lines,
                                 int64_t* max_line_points) {
  return guarded("locus_voronoi_bound", [&] {
    require(session != nullptr, "session is NULL");
    const int64_t nf = session->session.num_faces();
    // An edge point per mesh edge (<= 3 nf) plus a corner per face; <= 3 segments per face,
    // and a polyline of k segments has k + 1 points.
    if (max_points) *max_points = 4 * nf;
    if (max_lines) *max_lines = 3 * nf;
    if (max_line_points) *max_line_points = 6 * nf;
  });
}

locus_status locus_voronoi(locus_session* session, const locus_surface_point* generators, int64_t n_generators,
                           locus_voronoi_output* out, const locus_run_options* opts) {
  return session_run("locus_voronoi", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out != nullptr, "out is NULL");
    const locus::VoronoiResult r = s.voronoi(mesh_points(s, generators, n_generators, "generators"), cc.heat(), cc.ctx);
    out->n_points = static_cast<int64_t>(r.points.size() / 3);
    out->n_lines = static_cast<int64_t>(r.line_offsets.size()) - 1;
    out->n_line_points = static_cast<int64_t>(r.line_points.size());
    if (out->labels) std::copy(r.label.begin(), r.label.end(), out->labels);
    const auto check = [](const void* p, int64_t capacity, int64_t need, const char* what) {
      if (p && capacity < need)
        fail(ErrorCode::BadUsage, std::string(what) + " holds " + std::to_string(capacity) + " but the diagram has " +
                                      std::to_string(need) + " (locus_voronoi_bound gives capacities that suffice)");
    };
    check(out->points, out->points_capacity, out->n_points, "points_capacity");
    check(out->line_offsets, out->lines_capacity, out->n_lines, "lines_capacity");
    check(out->line_points, out->line_points_capacity, out->n_line_points, "line_points_capacity");
    if (out->points) std::copy(r.points.begin(), r.points.end(), out->points);
    if (out->line_offsets) std::copy(r.line_offsets.begin(), r.line_offsets.end(), out->line_offsets);
    if (out->line_points) std::copy(r.line_points.begin(), r.line_points.end(), out->line_points);
  });
}

locus_status locus_nncoords_prepare(locus_session* session, const locus_surface_point* sites, int64_t n_sites,
                                    const locus_run_options* opts, locus_nncoords_field** out) {
  if (out) *out = nullptr;
  return session_run("locus_nncoords_prepare", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out != nullptr, "out is NULL");
    const std::vector<locus::MeshPoint> p = mesh_points(s, sites, n_sites, "sites");
    *out = new locus_nncoords_field(s.prepare_natural_neighbors(p, cc.heat(), cc.ctx), s.num_vertices(), s.num_faces());
  });
}

locus_status locus_nncoords_query(const locus_nncoords_field* nn, const locus_surface_point* point, double* out_weights) {
  return guarded("locus_nncoords_query", [&] {
    require(nn != nullptr, "nn is NULL");
    require(point != nullptr, "point is NULL");
    require(out_weights != nullptr, "out_weights is NULL");
    const locus::MeshPoint q = mesh_point(nn->nv, nn->nf, *point, "point", -1);
    const locus::NaturalNeighborResult r = nn->field.coordinates(q);
    std::copy(r.weight.begin(), r.weight.end(), out_weights);
  });
}

int64_t locus_nncoords_site_count(const locus_nncoords_field* nn) {
  return count_of("locus_nncoords_site_count", nn, "nn is NULL",
                  [&] { return nn->field.num_sites(); });
}

void locus_nncoords_destroy(locus_nncoords_field* nn) {
  clear_error();
  delete nn;
}

locus_status locus_nncoords(locus_session* session, const locus_surface_point* sites, int64_t n_sites,
                            const locus_surface_point* point, double* out_weights, const locus_run_options* opts) {
  return session_run("locus_nncoords", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out_weights != nullptr, "out_weights is NULL");
    const std::vector<locus::MeshPoint> q = mesh_points(s, point, 1, "point");  // before the diagram: fails fast
    const std::vector<locus::MeshPoint> p = mesh_points(s, sites, n_sites, "sites");
    const locus::NaturalNeighborResult r = s.natural_neighbor_coordinates(p, q[0], cc.heat(), cc.ctx);
    std::copy(r.weight.begin(), r.weight.end(), out_weights);
  });
}

locus_status locus_skinning_weights(locus_session* session, const locus_surface_point* handles, int64_t n_handles,
                                    double* out, const locus_run_options* opts) {
  return session_run("locus_skinning_weights", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out != nullptr, "out is NULL");
    const std::vector<locus::MeshPoint> h = mesh_points(s, handles, n_handles, "handles");
    const locus::SkinningWeightsResult r = s.skinning_weights(h, cc.heat(), cc.ctx);
    std::copy(r.weight.begin(), r.weight.end(), out);
  });
}

locus_status locus_adf(locus_session* session, const int64_t* vertices, int64_t n_vertices, int32_t selected_inversion,
                       double* out, const locus_run_options* opts) {
  return session_run("locus_adf", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out != nullptr, "out is NULL");
    const std::vector<int32_t> v = optional_vertex_ids(s, vertices, n_vertices, "vertices");
    const std::vector<double> r = s.auto_diffusion(
        v, cc.heat(), selected_inversion ? locus::DiagonalMethod::SelectedInversion : locus::DiagonalMethod::Subset,
        cc.ctx);
    std::copy(r.begin(), r.end(), out);
  });
}

locus_status locus_hks(locus_session* session, const double* t_factors, int64_t n_times, const int64_t* vertices,
                       int64_t n_vertices, int32_t selected_inversion, double* out, const locus_run_options* opts) {
  return session_run("locus_hks", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out != nullptr, "out is NULL");
    require(t_factors != nullptr, "t_factors is NULL");
    if (n_times < 1 || n_times > 1000)
      fail(ErrorCode::BadUsage, "n_times = " + std::to_string(n_times) + " is not in 1..1000");
    std::vector<locus::HeatQuery> times;
    for (int64_t j = 0; j < n_times; ++j) {
      if (!(t_factors[j] > 0) || !std::isfinite(t_factors[j]))
        fail(ErrorCode::BadUsage, "t_factors[" + std::to_string(j) + "] = " + std::to_string(t_factors[j]) +
                                      " is not a finite positive number");
      times.push_back(locus::HeatQuery{t_factors[j], 0.0});
    }
    const std::vector<int32_t> v = optional_vertex_ids(s, vertices, n_vertices, "vertices");
    const std::vector<double> r = s.heat_kernel_signature(
        times, v, selected_inversion ? locus::DiagonalMethod::SelectedInversion : locus::DiagonalMethod::Subset,
        cc.ctx);
    std::copy(r.begin(), r.end(), out);
  });
}

locus_status locus_heat_exchange(locus_session* session, const int64_t* sources, int64_t n_sources,
                                 const int64_t* targets, int64_t n_targets, double* out_targets,
                                 const locus_run_options* opts) {
  return session_run("locus_heat_exchange", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out_targets != nullptr, "out_targets is NULL");
    const std::vector<int32_t> src = vertex_ids(s, sources, n_sources, "sources");
    const std::vector<int32_t> tgt = vertex_ids(s, targets, n_targets, "targets");
    const std::vector<double> r = s.heat_exchange(src, tgt, cc.heat(), cc.ctx);
    std::copy(r.begin(), r.end(), out_targets);
  });
}

}  // extern "C"
