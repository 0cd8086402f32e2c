// Lloyd's method with heat-diffusion Voronoi cells and centroids, localized
// (pipelines/include/locus/pipelines/voronoi/cvt_lloyd.hpp; thesis §3.7.1, §3.4-3.6), and the R^6 lift of the
// anisotropic variant.
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/core/host_allocator.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <queue>
#include <string>

#include "locus/kernels/heat/heat_batch.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/index_min_heap.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_selective.hpp"
#include "locus/kernels/parallel/batch_graph.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/cvt_quality.hpp"
#include "locus/pipelines/voronoi/heat_centroid.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "locus/pipelines/voronoi/voronoi_cell_partition.hpp"
#include "locus/kernels/parallel/progress_ticker.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

CscMatrix heat_operator_from_positions(const Mesh& m, std::span<const double> pos, int dim, double t,
                                       HostVector<double>& mass, double& mean_edge) {
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  if (dim < 1 || pos.size() != static_cast<size_t>(n) * dim)
    fail(ErrorCode::BadUsage, "heat operator from positions: expected " + std::to_string(dim) + " values per vertex");
  auto len2 = [&](int32_t a, int32_t b) {
    double s = 0;
    for (int c = 0; c < dim; ++c) {
      const double d = pos[static_cast<size_t>(a) * dim + c] - pos[static_cast<size_t>(b) * dim + c];
      s += d * d;
    }
    return s;
  };
  mass.assign(n, 0.0);
  std::vector<int32_t> ii, jj;
  std::vector<double> vv;
  ii.reserve(static_cast<size_t>(n) + 3 * static_cast<size_t>(nf));
  jj.reserve(ii.capacity());
  vv.reserve(ii.capacity());
  std::vector<double> diag(n, 0.0);
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    // l2[k]: squared length of the edge opposite corner k.
    const double l2[3] = {len2(v[1], v[2]), len2(v[2], v[0]), len2(v[0], v[1])};
    double l[3] = {std::sqrt(l2[0]), std::sqrt(l2[1]), std::sqrt(l2[2])};
    // Heron in Kahan's stable form (a >= b >= c), exact for needle triangles.
    std::sort(l, l + 3, std::greater<double>());
    const double a = l[0], b = l[1], c = l[2];
    const double q = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
    const double area = q > 0 ? 0.25 * std::sqrt(q) : 0.0;
    if (!(area > 0) || !std::isfinite(area))
      fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has zero area in the lifted metric");
    for (int k = 0; k < 3; ++k) {
      mass[v[k]] += area / 3;
      const int32_t i = v[(k + 1) % 3], j = v[(k + 2) % 3];
      const double w = 0.5 * (l2[(k + 1) % 3] + l2[(k + 2) % 3] - l2[k]) / (4 * area);  // cot at k, halved
      ii.push_back(i);
      jj.push_back(j);
      vv.push_back(-t * w);
      diag[i] += t * w;
      diag[j] += t * w;
    }
  }
  for (int32_t v = 0; v < n; ++v) {
    ii.push_back(v);
    jj.push_back(v);
    vv.push_back(mass[v] + diag[v]);
  }
  const Edges e = unique_edges(m);
  double sum = 0;
  for (size_t k = 0; k < e.e0.size(); ++k) sum += std::sqrt(len2(e.e0[k], e.e1[k]));
  mean_edge = e.e0.empty() ? 0.0 : sum / static_cast<double>(e.e0.size());
  return lower_from_triplets(n, ii, jj, vv);
}

std::vector<double> lifted_positions(const Mesh& m, double lambda) {
  const int32_t n = m.num_vertices();
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  const HostVector<double>* X[3] = {&m.x, &m.y, &m.z};
  for (int c = 0; c < 3; ++c)
    for (int32_t v = 0; v < n; ++v) {
      lo[c] = std::min(lo[c], (*X[c])[v]);
      hi[c] = std::max(hi[c], (*X[c])[v]);
    }
  const double side = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!(side > 0) || !std::isfinite(side)) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no extent");
  const HostVector<double> nrm = area_weighted_normals(m);
  std::vector<double> p(static_cast<size_t>(n) * 6);
  for (int32_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) {
      p[6 * static_cast<size_t>(v) + c] = ((*X[c])[v] - lo[c]) / side;
      p[6 * static_cast<size_t>(v) + 3 + c] = lambda * nrm[3 * static_cast<size_t>(v) + c];
    }
  return p;
}

namespace {

// Morton order of the sites' positions: batches of 8 consecutive sites are compact,
// so the unions of their neighborhoods stay small.
std::vector<int32_t> spatial_order(const Mesh& m, std::span<const SurfacePoint> sites) {
  const size_t ns = sites.size();
  std::vector<std::array<double, 3>> p(ns);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t s = 0; s < ns; ++s) {
    p[s] = surface_point_position(m, sites[s]);
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], p[s][c]);
      hi[c] = std::max(hi[c], p[s][c]);
    }
  }
  auto spread = [](uint64_t x) {  // 21 bits -> every third bit
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
  };
  std::vector<std::pair<uint64_t, int32_t>> key(ns);
  for (size_t s = 0; s < ns; ++s) {
    uint64_t code = 0;
    for (int c = 0; c < 3; ++c) {
      const double ext = hi[c] - lo[c];
      const double f = ext > 0 ? (p[s][c] - lo[c]) / ext : 0.0;
      code |= spread(static_cast<uint64_t>(std::clamp(f, 0.0, 1.0) * 2097151.0)) << c;
    }
    key[s] = {code, static_cast<int32_t>(s)};
  }
  std::sort(key.begin(), key.end());
  std::vector<int32_t> order(ns);
  for (size_t s = 0; s < ns; ++s) order[s] = key[s].second;
  return order;
}

// Vertices within graph distance `radius` of a surface point, sorted: the patch
// grower's geodesic ball from the corners of the point's support, each at its
// distance from the point (kernels/include/locus/kernels/mesh/patch_grower.hpp).
std::vector<int32_t> geodesic_ball(const Mesh& m, const Adjacency& adj, std::span<const double> edge_length,
                                   const SurfacePoint& s, double radius, GrowWorkspace& w) {
  const auto p = surface_point_position(m, s);
  int32_t sv[3];
  double sw[3];
  const int cnt = surface_point_support(m, s, sv, sw);
  GrowSeed seeds[3];
  for (int k = 0; k < cnt; ++k)
    seeds[k] = {sv[k], std::sqrt((m.x[sv[k]] - p[0]) * (m.x[sv[k]] - p[0]) + (m.y[sv[k]] - p[1]) * (m.y[sv[k]] - p[1]) +
                                 (m.z[sv[k]] - p[2]) * (m.z[sv[k]] - p[2]))};
  GrowOptions o;
  o.mode = GrowMode::Geodesic;
  o.max_radius = radius;
  o.radius_rule = RadiusRule::PruneBeyond;
  HostVector<int32_t> out;
  grow_vertices(adj, edge_length, std::span<const GrowSeed>(seeds, static_cast<size_t>(cnt)), o, w, out);
  std::sort(out.begin(), out.end());
  return std::vector<int32_t>(out);
}

// Graph-geodesic Voronoi cells of the sites: one multi-source Dijkstra on the
// edge lengths from every site's support corners (at |corner - site|). Sites
// are seeded in id order and a vertex changes site only for a strictly smaller
// distance: deterministic. Labels -1 where no site reaches (a component
// without sites).
HostVector<int32_t> dijkstra_cells(const Mesh& m, const Adjacency& adj, std::span<const SurfacePoint> sites) {
  const int32_t n = m.num_vertices();
  const HostVector<double> len = adjacency_edge_lengths(m, adj);
  HostVector<double> dist(n, INFINITY);
  HostVector<int32_t> label(n, -1), pos(n, -1), heap;
  auto relax = [&](int32_t w, double d, int32_t s) {
    if (pos[w] == -2 || !(d < dist[w])) return;
    dist[w] = d;
    label[w] = s;
    if (pos[w] < 0) {
      heap.push_back(w);
      pos[w] = static_cast<int32_t>(heap.size()) - 1;
    }
    index_heap_sift_up(heap, dist.data(), pos.data(), pos[w]);
  };
  for (int32_t s = 0; s < static_cast<int32_t>(sites.size()); ++s) {
    const auto p = surface_point_position(m, sites[s]);
    int32_t sv[3];
    double sw[3];
    const int cnt = surface_point_support(m, sites[s], sv, sw);
    for (int k = 0; k < cnt; ++k)
      relax(sv[k], std::sqrt((m.x[sv[k]] - p[0]) * (m.x[sv[k]] - p[0]) + (m.y[sv[k]] - p[1]) * (m.y[sv[k]] - p[1]) +
                             (m.z[sv[k]] - p[2]) * (m.z[sv[k]] - p[2])),
            s);
  }
  while (!heap.empty()) {
    const int32_t v = index_heap_pop_min(heap, dist.data(), pos.data());
    pos[v] = -2;  // settled
    for (int64_t q = adj.offsets[v]; q < adj.offsets[v + 1]; ++q) relax(adj.neighbors[q], dist[v] + len[q], label[v]);
  }
  return label;
}

// Cells as CSR (vertices ascending within a cell) and the cell adjacency graph.
struct Cells {
  HostVector<int64_t> offsets;  // ns + 1
  HostVector<int32_t> verts;
  HostVector<int64_t> adj_offsets;
  HostVector<int32_t> adj;
};
Cells build_cells(const Edges& edges, std::span<const int32_t> label, int32_t ns) {
  Cells c;
  c.offsets.assign(static_cast<size_t>(ns) + 1, 0);
  for (int32_t l : label) ++c.offsets[l + 1];
  for (int32_t s = 0; s < ns; ++s) c.offsets[s + 1] += c.offsets[s];
  c.verts.resize(label.size());
  std::vector<int64_t> fill(c.offsets.begin(), c.offsets.end() - 1);
  for (size_t v = 0; v < label.size(); ++v) c.verts[fill[label[v]]++] = static_cast<int32_t>(v);
  // Cell adjacency: the labels across every edge between two cells, bucketed by
  // cell (CSR with repeats), then sorted and deduplicated per cell in parallel.
  std::vector<int64_t> raw_off(static_cast<size_t>(ns) + 1, 0);
  for (size_t k = 0; k < edges.e0.size(); ++k) {
    const int32_t a = label[edges.e0[k]], b = label[edges.e1[k]];
    if (a != b) {
      ++raw_off[a + 1];
      ++raw_off[b + 1];
    }
  }
  for (int32_t s = 0; s < ns; ++s) raw_off[s + 1] += raw_off[s];
  HostVector<int32_t> raw(static_cast<size_t>(raw_off[ns]));
  fill.assign(raw_off.begin(), raw_off.end() - 1);
  for (size_t k = 0; k < edges.e0.size(); ++k) {
    const int32_t a = label[edges.e0[k]], b = label[edges.e1[k]];
    if (a != b) {
      raw[fill[a]++] = b;
      raw[fill[b]++] = a;
    }
  }
  std::vector<int64_t> count(ns);
  tbb::parallel_for(0, ns, [&](int32_t s) {
    auto first = raw.begin() + raw_off[s], last = raw.begin() + raw_off[s + 1];
    std::sort(first, last);
    count[s] = std::unique(first, last) - first;
  });
  c.adj_offsets.assign(static_cast<size_t>(ns) + 1, 0);
  for (int32_t s = 0; s < ns; ++s) c.adj_offsets[s + 1] = c.adj_offsets[s] + count[s];
  c.adj.resize(static_cast<size_t>(c.adj_offsets[ns]));
  for (int32_t s = 0; s < ns; ++s)
    std::copy(raw.begin() + raw_off[s], raw.begin() + raw_off[s] + count[s], c.adj.begin() + c.adj_offsets[s]);
  return c;
}

// Cell s, its neighbor cells and their neighbors (sorted cell ids), appended to `out`.
void two_ring_cells(const Cells& c, int32_t s, std::vector<int32_t>& out) {
  out.push_back(s);
  for (int64_t p = c.adj_offsets[s]; p < c.adj_offsets[s + 1]; ++p) {
    const int32_t a = c.adj[p];
    out.push_back(a);
    for (int64_t q = c.adj_offsets[a]; q < c.adj_offsets[a + 1]; ++q) out.push_back(c.adj[q]);
  }
}

void cells_to_vertices(const Cells& c, std::vector<int32_t>& cells, HostVector<int32_t>& verts) {
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  verts.clear();
  // Cells are disjoint: the concatenation is already unique (the solve plan needs no order).
  for (int32_t a : cells) verts.insert(verts.end(), c.verts.begin() + c.offsets[a], c.verts.begin() + c.offsets[a + 1]);
}

// Batches of 8 cells that are neighbors in the cell adjacency graph, grown
// breadth-first from the first unassigned cell in Morton order: the union of a
// batch's two-ring neighborhoods (its kept set) is then close to the two rings
// around one compact patch of 8 cells rather than around 8 scattered ones.
std::vector<int32_t> cluster_order(const Cells& c, std::span<const int32_t> morton) {
  const int32_t ns = static_cast<int32_t>(morton.size());
  std::vector<int32_t> out, queue;
  out.reserve(ns);
  std::vector<uint8_t> taken(ns, 0), queued(ns, 0);
  size_t next = 0;
  while (static_cast<int32_t>(out.size()) < ns) {
    const size_t batch_start = out.size();
    queue.clear();
    size_t head = 0;
    while (out.size() - batch_start < static_cast<size_t>(kLanes) && static_cast<int32_t>(out.size()) < ns) {
      if (head == queue.size()) {  // patch exhausted: the next unassigned cell in Morton order
        while (taken[morton[next]]) ++next;
        queue.push_back(morton[next]);
        queued[morton[next]] = 1;
      }
      const int32_t s = queue[head++];
      taken[s] = 1;
      out.push_back(s);
      for (int64_t p = c.adj_offsets[s]; p < c.adj_offsets[s + 1]; ++p) {
        const int32_t a = c.adj[p];
        if (!taken[a] && !queued[a]) {
          queued[a] = 1;
          queue.push_back(a);
        }
      }
    }
    for (int32_t q : queue) queued[q] = 0;
  }
  return out;
}

struct CentroidMsg {
  int32_t cells[kLanes];
  HeatCentroid result[kLanes];
  int lanes = 0;
  int32_t batch = 0;
  int64_t kept = 0;
  int64_t reads = 0, label_reads = 0;  // factor entries read (count_reads)
  double solve_cpu_s = 0;
  double energy[kLanes] = {};
  double area_centroid[kLanes][3] = {};  // sum_i b_i x_i / sum_i b_i of the cell's source
  int64_t fallback = 0;
};

// Tangential distance between a surface point and a point off the surface: the
// difference with its component along the surface normal there removed.
double tangential_distance(const Mesh& m, const CentroidGeometry& g, const SurfacePoint& p, const double q[3]) {
  const auto x = surface_point_position(m, p);
  double nrm[3] = {0, 0, 0};
  if (p.face >= 0) {
    const int32_t a = m.f0[p.face], b = m.f1[p.face], c = m.f2[p.face];
    const double e1[3] = {m.x[b] - m.x[a], m.y[b] - m.y[a], m.z[b] - m.z[a]};
    const double e2[3] = {m.x[c] - m.x[a], m.y[c] - m.y[a], m.z[c] - m.z[a]};
    nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
  } else {
    for (int k = 0; k < 3; ++k) nrm[k] = g.normals[3 * static_cast<size_t>(p.vertex) + k];
  }
  const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
  double d[3] = {q[0] - x[0], q[1] - x[1], q[2] - x[2]};
  if (len > 0) {
    const double dn = (d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2]) / (len * len);
    for (int k = 0; k < 3; ++k) d[k] -= dn * nrm[k];
  }
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

struct CentroidScratch {
  HeatBatch batch;
  HostVector<double> dense;  // n, zero between uses
  std::vector<int32_t> cells, touched;
  HostVector<int32_t> pos;  // n, -1 between uses: position of a kept vertex in the batch's solution
  std::vector<double> weights;
  std::vector<uint8_t> read_mark;   // count_reads scratch
  std::vector<int32_t> label_support;
  SolvePlan label_plan;
  PlanWorkspace label_pws;
};


// sum_i b_i x_i / sum_i b_i: the exact area centroid (R^3) of a cell whose load is b
// (the hat functions reproduce x on every triangle).
void area_centroid(const Mesh& m, std::span<const int32_t> ids, std::span<const double> w, double out[3]) {
  double s = 0, sx = 0, sy = 0, sz = 0;
  for (size_t k = 0; k < ids.size(); ++k) {
    s += w[k];
    sx += w[k] * m.x[ids[k]];
    sy += w[k] * m.y[ids[k]];
    sz += w[k] * m.z[ids[k]];
  }
  out[0] = s > 0 ? sx / s : 0.0;
  out[1] = s > 0 ? sy / s : 0.0;
  out[2] = s > 0 ? sz / s : 0.0;
}

// Hottest vertex of every lane in one pass: largest heat, smallest id on ties (deterministic).
void hottest_vertices(const HeatBatch& hb, int32_t best[kLanes]) {
  double bv[kLanes];
  std::fill(best, best + kLanes, -1);
  std::fill(bv, bv + kLanes, -INFINITY);
  const int32_t cnt = hb.count();
  for (int32_t k = 0; k < cnt; ++k) {
    const double* row = hb.values.data() + static_cast<size_t>(k) * kLanes;
    const int32_t id = hb.id(k);
    for (int l = 0; l < kLanes; ++l)
      if (row[l] > bv[l] || (row[l] == bv[l] && id < best[l])) {
        bv[l] = row[l];
        best[l] = id;
      }
  }
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
    const int32_t v = p.vertex >= 0 ? p.vertex : m.face_vertices[static_cast<size_t>(m.face_offsets[p.face])];
    has_site[static_cast<size_t>(comp[v])] = 1;
  }
  for (int32_t v = 0; v < n; ++v)
    if (comp[v] >= 0 && !has_site[static_cast<size_t>(comp[v])])
      fail(ErrorCode::BadInput, "cvt: the connected component containing vertex " + std::to_string(v) +
                                    " has no site (the mesh has " + std::to_string(nc) +
                                    " components; every component needs at least one site)");
}

// given: m's derived data, or null to derive it here (after the requirement checks,
// so the errors come in the same order); `own` holds it then.
const MeshDerived& check_lloyd_input(const Mesh& m, const MeshDerived* given, std::span<const SurfacePoint> sites,
                                     const LloydOptions& opt, MeshDerived& own) {
  const int32_t ns = static_cast<int32_t>(sites.size());
  if (ns < 1) fail(ErrorCode::BadUsage, "cvt: at least one site");
  if (opt.iterations < 0) fail(ErrorCode::BadUsage, "cvt: negative iteration count");
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

// The operators of one run: the cells' (opt.prepared, or M - t L of the mesh or of
// its R^6 lift) and the centroids' (the same, or with t_centroid_factor a second
// numeric factor on the same symbolic factor), and the face areas in the cells'
// metric. Filled in place: H and Hc may point at H_own and Hc_own.
struct LloydOperators {
  HeatDiffusion H_own, Hc_own;
  const HeatDiffusion* H = nullptr;
  const HeatDiffusion* Hc = nullptr;
  HostVector<double> area_op;  // face areas in the operator's metric (lifted when anisotropic)
};

void prepare_lloyd_operators(const Mesh& m, const MeshDerived& d, const LloydOptions& opt, const HostVector<double>& area_r3,
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
    if (opt.prepared->n != n || opt.prepared->mass.size() != static_cast<size_t>(n))
      fail(ErrorCode::BadUsage, "cvt: the prepared operator belongs to another mesh");
    ops.area_op = area_r3;
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
    ops.area_op = opt.anisotropy > 0 ? face_areas_from_positions(m, lifted, 6) : area_r3;
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
}

// What the Lloyd iterations read and never change.
struct LloydInputs {
  const Mesh& m;
  const LloydOptions& opt;
  const RunContext& ctx;
  const HeatDiffusion& H;   // cells (labels)
  const HeatDiffusion& Hc;  // centroids
  const CentroidGeometry& geo;
  const Edges& edges;
  const VertexStars& stars;          // in the operator's metric
  const HostVector<double>& area_r3;
  const HostVector<double>& mass_r3;
  double h_r3;
  int threads;                       // of the arena of the cell partitions (>= 1)
};

// This iteration's centroid step: one slot per cell, filled as the batches arrive
// (arrival order is irrelevant), and per-batch factor reads (count_reads).
struct CentroidSlots {
  std::vector<HeatCentroid> cent;
  std::vector<double> cell_energy;
  std::vector<uint8_t> has;
  std::vector<double> bias;
  std::vector<int64_t> centroid_reads, label_reads;
  size_t kept_base = 0;  // this iteration's first entry of kept_fraction_
  int64_t fallback = 0;
};

// Lloyd's iterations on the current sites: labels, batches of neighboring cells,
// their sources, heat centroids and refinement, statistics, the move; then the
// final labels. Writes the result's per-iteration series and totals.
class LloydLoop {
 public:
  LloydLoop(const LloydInputs& in, std::vector<SurfacePoint>& sites, std::vector<std::vector<int32_t>> nb,
            LloydResult& r)
      : in_(in), m_(in.m), opt_(in.opt), ctx_(in.ctx), local_(in.opt.solver == LloydOptions::Solver::Local),
        n_(in.m.num_vertices()), ns_(static_cast<int32_t>(sites.size())), sites_(sites), nb_(std::move(nb)), r_(r),
        full_entries_(in.opt.count_reads ? factor_entries(*in.H.factor.symbolic) : 0) {}

  void iterate(int32_t it);
  void finish();
  // Localized first labels from given cells (e.g. dijkstra_cells) instead of
  // per-site neighborhoods: batches and kept sets as every later iteration's.
  void first_cells(std::span<const int32_t> label);

 private:
  template <class F>
  void in_arena(F&& f) {  // reused per (thread, concurrency): an arena per call leaks inside oneTBB
    run_with_threads(in_.threads, f);
  }
  void labels_of_sites();
  // This iteration's share of the progress (iteration it of n: [it, it + 1) / (n + 1); the final labels last).
  RunContext step_context(int32_t it, double begin, double end) const {
    const double n = std::max(1, opt_.iterations) + 1.0;
    return ctx_.sub((it + begin) / n, (it + end) / n);
  }
  CentroidSlots centroid_slots(int32_t nbatch);
  std::shared_ptr<CentroidMsg> solve_centroid_batch(int32_t b, std::span<const std::array<double, 3>> before);
  void add_cell_source(CentroidScratch& cs, CentroidMsg& msg, int l, int32_t c, const std::array<double, 3>& p);
  void count_batch_reads(CentroidScratch& cs, CentroidMsg& msg, int32_t b);
  void refine_centroids(CentroidScratch& cs, CentroidMsg& msg);
  void store(const CentroidMsg& msg, CentroidSlots& slots);
  void record_statistics(CentroidSlots& slots, int32_t nbatch);
  void move_sites(const CentroidSlots& slots, std::span<const std::array<double, 3>> before);

  const LloydInputs in_;
  const Mesh& m_;
  const LloydOptions& opt_;
  const RunContext& ctx_;
  RunContext labels_ctx_;  // the labels' part of the current iteration (one monotone fraction per call)
  const bool local_;
  const int32_t n_, ns_;
  std::vector<SurfacePoint>& sites_;
  std::vector<std::vector<int32_t>> nb_;  // first neighborhoods (localized), until the first labels
  LloydResult& r_;
  HeatVoronoi V_;
  Cells cells_;
  tbb::enumerable_thread_specific<CentroidScratch> cscratch_;
  std::vector<double> kept_fraction_;  // per centroid batch, summed in batch order at the end
  // Batches (runs of 8 in `order_`) and, localized, each batch's kept set: the union of
  // its cells and their two rings of neighbor cells. Built by the centroid step from
  // the labels of this iteration and reused by the next labels (same batches: the
  // sites are the centroids of these cells), so no neighborhood is built twice.
  std::vector<int32_t> order_;
  std::vector<HostVector<int32_t>> batch_kept_;
  const int64_t full_entries_;
  double centroid_read_sum_ = 0, label_read_sum_ = 0;
  int64_t read_batches_ = 0;
};

void LloydLoop::first_cells(std::span<const int32_t> label) {
  in_arena([&] {
    cells_ = build_cells(in_.edges, label, ns_);
    order_ = cluster_order(cells_, spatial_order(m_, sites_));
    const int32_t nbatch = (ns_ + kLanes - 1) / kLanes;
    batch_kept_.assign(nbatch, {});
    tbb::parallel_for(0, nbatch, [&](int32_t b) {
      std::vector<int32_t> cells;
      for (int32_t i = b * kLanes; i < std::min(ns_, (b + 1) * kLanes); ++i) two_ring_cells(cells_, order_[i], cells);
      cells_to_vertices(cells_, cells, batch_kept_[b]);
    });
  });
  nb_ = {};
}

void LloydLoop::labels_of_sites() {
  BatchStopwatch psw;
  if (order_.empty()) order_ = spatial_order(m_, sites_);
  if (local_ && !batch_kept_.empty()) {
    V_ = heat_voronoi_batched(in_.H, m_, sites_, order_, batch_kept_, labels_ctx_);
  } else {  // first labels: per-site Dijkstra balls (localized) or full solves
    V_ = heat_voronoi(in_.H, m_, sites_, local_ ? std::span<const std::vector<int32_t>>(nb_)
                                                 : std::span<const std::vector<int32_t>>(),
                      order_, labels_ctx_);
    nb_ = {};
  }
  r_.unreached += V_.unreached;
  r_.label_solve_cpu_s += V_.solve_cpu_s;
  r_.labels_s += psw.lap();
  for (int32_t v = 0; v < n_; ++v)
    if (V_.label[v] < 0)
      fail(ErrorCode::Numerical, "cvt: vertex " + std::to_string(v) + " received heat from no site");
  in_arena([&] { cells_ = build_cells(in_.edges, V_.label, ns_); });
  r_.partition_s += psw.lap();
}

CentroidSlots LloydLoop::centroid_slots(int32_t nbatch) {
  CentroidSlots s;
  s.cent.resize(ns_);
  s.cell_energy.assign(ns_, 0.0);
  s.has.assign(ns_, 0);
  s.bias.assign(ns_, 0.0);
  if (local_) batch_kept_.assign(nbatch, {});
  s.kept_base = kept_fraction_.size();
  s.centroid_reads.assign(nbatch, 0);
  s.label_reads.assign(nbatch, 0);
  kept_fraction_.resize(s.kept_base + nbatch, 0.0);
  return s;
}

// Lane l of a centroid batch: cell c's Euclidean CVT energy w.r.t. its current site
// p (diagnostic), its source (the split triangles or the vertex masses of the cell)
// added to the batch, and that source's area centroid.
void LloydLoop::add_cell_source(CentroidScratch& cs, CentroidMsg& msg, int l, int32_t c,
                                const std::array<double, 3>& p) {
  const Mesh& m = m_;
  const std::span<const int32_t> cv(cells_.verts.data() + cells_.offsets[c],
                                    static_cast<size_t>(cells_.offsets[c + 1] - cells_.offsets[c]));
  {  // Euclidean CVT energy of the cell w.r.t. its current site (diagnostic)
    double e = 0;
    for (int32_t v : cv)
      e += in_.mass_r3[v] * ((m.x[v] - p[0]) * (m.x[v] - p[0]) + (m.y[v] - p[1]) * (m.y[v] - p[1]) +
                             (m.z[v] - p[2]) * (m.z[v] - p[2]));
    msg.energy[l] = e;
  }
  cs.touched.clear();
  cs.weights.clear();
  if (opt_.split_faces) {  // int_C phi_i over the split triangles (eqs. 3.9-3.11), this cell only
    accumulate_cell_load(in_.stars, V_, c, cv, cs.dense, cs.touched, msg.fallback);
    for (int32_t v : cs.touched) {
      cs.weights.push_back(cs.dense[v]);
      cs.dense[v] = 0.0;
    }
    cs.batch.add_source(cs.touched, cs.weights);
    area_centroid(m, cs.touched, cs.weights, msg.area_centroid[l]);
  } else {
    for (int32_t v : cv) cs.weights.push_back(in_.Hc.mass[v]);  // M chi_C (eqs. 3.7, 3.10)
    cs.batch.add_source(cv, cs.weights);
    area_centroid(m, cv, cs.weights, msg.area_centroid[l]);
  }
}

// count_reads: the factor entries this batch's centroid solve read and those the
// next labels' solve of the same batch will read (the sites' supports on the same
// kept set).
void LloydLoop::count_batch_reads(CentroidScratch& cs, CentroidMsg& msg, int32_t b) {
  const HeatBatch& hb = cs.batch;
  msg.reads = selective_solve_reads(*in_.Hc.factor.symbolic, hb.plan(), cs.read_mark);
  cs.label_support.clear();
  for (int l = 0; l < msg.lanes; ++l) {
    int32_t sv[3];
    double sw[3];
    const int c = surface_point_support(m_, sites_[order_[b * kLanes + l]], sv, sw);
    cs.label_support.insert(cs.label_support.end(), sv, sv + c);
  }
  plan_selective_solve(*in_.H.factor.symbolic, cs.label_support, hb.kept, cs.label_plan, cs.label_pws);
  msg.label_reads = selective_solve_reads(*in_.H.factor.symbolic, cs.label_plan, cs.read_mark);
}

// The centroid of every lane's cell from the batch's solution: its hottest vertex,
// refined by the quadratic fit (heat_centroid.hpp); empty cells keep their site.
void LloydLoop::refine_centroids(CentroidScratch& cs, CentroidMsg& msg) {
  const HeatBatch& hb = cs.batch;
  const int32_t cnt = hb.count();
  int32_t best[kLanes];
  hottest_vertices(hb, best);
  // Positions of the kept vertices in the solution (localized): the fits read
  // their rings through it (-1 = not kept, heat zero).
  if (local_ && opt_.refine) {
    if (cs.pos.size() != static_cast<size_t>(n_)) cs.pos.assign(n_, -1);
    for (int32_t k = 0; k < cnt; ++k) cs.pos[hb.id(k)] = k;
  }
  for (int l = 0; l < msg.lanes; ++l) {
    const int32_t c = msg.cells[l];
    if (cells_.offsets[c + 1] == cells_.offsets[c]) {
      msg.result[l].hottest = -1;  // empty cell: the site stays
      continue;
    }
    if (!opt_.refine) {
      msg.result[l].hottest = best[l];
      msg.result[l].point = vertex_point(best[l]);
    } else if (local_) {
      msg.result[l] = refine_heat_maximum(m_, in_.geo, hb.values, cs.pos, l, best[l], opt_.fit_rings, opt_.fit_sigma);
    } else {
      for (int32_t k = 0; k < cnt; ++k) cs.dense[k] = hb.values[static_cast<size_t>(k) * kLanes + l];
      msg.result[l] = refine_heat_maximum(m_, in_.geo, cs.dense, best[l], opt_.fit_rings, opt_.fit_sigma);
    }
  }
  if (local_ && opt_.refine)
    for (int32_t k = 0; k < cnt; ++k) cs.pos[hb.id(k)] = -1;
  if (!local_) std::fill(cs.dense.begin(), cs.dense.end(), 0.0);
}

// Batch b of 8 cells (runs of 8 in order_): sources, kept set (localized), one
// 8-lane solve, centroids.
std::shared_ptr<CentroidMsg> LloydLoop::solve_centroid_batch(int32_t b,
                                                             std::span<const std::array<double, 3>> before) {
  CentroidScratch& cs = cscratch_.local();
  if (cs.dense.size() != static_cast<size_t>(n_)) cs.dense.assign(n_, 0.0);
  auto msg = std::make_shared<CentroidMsg>();
  HeatBatch& hb = cs.batch;
  hb.clear_sources();
  hb.kept.clear();
  cs.cells.clear();
  msg->lanes = std::min(kLanes, ns_ - b * kLanes);
  msg->batch = b;
  for (int l = 0; l < msg->lanes; ++l) {
    const int32_t c = order_[b * kLanes + l];
    msg->cells[l] = c;
    add_cell_source(cs, *msg, l, c, before[c]);
    if (local_) two_ring_cells(cells_, c, cs.cells);
  }
  if (local_) {
    cells_to_vertices(cells_, cs.cells, hb.kept);
    batch_kept_[b] = hb.kept;  // this batch's slot: the next labels solve on it
  }
  const double c0 = thread_cpu_seconds();
  solve_heat_batch(in_.Hc, hb);
  msg->solve_cpu_s = thread_cpu_seconds() - c0;
  if (opt_.count_reads && local_) count_batch_reads(cs, *msg, b);
  msg->kept = hb.count();
  refine_centroids(cs, *msg);
  return msg;
}

void LloydLoop::store(const CentroidMsg& msg, CentroidSlots& slots) {  // one slot per cell
  for (int l = 0; l < msg.lanes; ++l) {
    slots.cent[msg.cells[l]] = msg.result[l];
    slots.cell_energy[msg.cells[l]] = msg.energy[l];
    slots.has[msg.cells[l]] = 1;
    if (msg.result[l].hottest >= 0)
      slots.bias[msg.cells[l]] = tangential_distance(m_, in_.geo, msg.result[l].point, msg.area_centroid[l]);
  }
  slots.fallback += msg.fallback;  // integer: order-independent
  kept_fraction_[slots.kept_base + msg.batch] = static_cast<double>(msg.kept) / n_;
  slots.centroid_reads[msg.batch] = msg.reads;
  r_.centroid_solve_cpu_s += msg.solve_cpu_s;
  slots.label_reads[msg.batch] = msg.label_reads;
}

// Read fractions (count_reads), the CVT energy and the centroid bias of the iteration.
void LloydLoop::record_statistics(CentroidSlots& slots, int32_t nbatch) {
  if (opt_.count_reads && local_) {  // batch order: deterministic sums
    const double full = 2.0 * static_cast<double>(full_entries_);
    for (int32_t b = 0; b < nbatch; ++b) {
      centroid_read_sum_ += static_cast<double>(slots.centroid_reads[b]) / full;
      label_read_sum_ += static_cast<double>(slots.label_reads[b]) / full;
    }
    read_batches_ += nbatch;
  }
  r_.energy.push_back(std::accumulate(slots.cell_energy.begin(), slots.cell_energy.end(), 0.0));  // fixed cell order
  std::vector<double>& bias = slots.bias;
  double b2 = 0;
  for (double b : bias) b2 += b * b;  // fixed cell order
  r_.centroid_bias.push_back(std::sqrt(b2 / ns_) / in_.h_r3);
  std::nth_element(bias.begin(), bias.begin() + ns_ / 2, bias.end());
  r_.centroid_bias_median.push_back(bias[ns_ / 2] / in_.h_r3);
}

// The sites move to their cells' centroids (empty cells keep theirs); RMS move.
void LloydLoop::move_sites(const CentroidSlots& slots, std::span<const std::array<double, 3>> before) {
  for (int32_t s = 0; s < ns_; ++s) {  // fixed cell order
    if (!slots.has[s]) fail(ErrorCode::Numerical, "cvt: cell " + std::to_string(s) + " got no centroid");
    if (slots.cent[s].hottest < 0) {
      ++r_.empty_cells;
      continue;
    }
    sites_[s] = slots.cent[s].point;
  }
  double mv = 0;
  for (int32_t s = 0; s < ns_; ++s) {
    const auto p = surface_point_position(m_, sites_[s]);
    mv += (p[0] - before[s][0]) * (p[0] - before[s][0]) + (p[1] - before[s][1]) * (p[1] - before[s][1]) +
          (p[2] - before[s][2]) * (p[2] - before[s][2]);
  }
  r_.moved.push_back(std::sqrt(mv / ns_) / in_.h_r3);
}

void LloydLoop::iterate(int32_t it) {
  ctx_.check_cancel();
  BatchStopwatch isw;
  labels_ctx_ = step_context(it, 0.0, 0.5);
  labels_of_sites();
  BatchStopwatch psw;
  // New batches from the new cells (compact patches of the cell graph).
  order_ = cluster_order(cells_, spatial_order(m_, sites_));
  r_.neighborhood_s += psw.lap();
  if (opt_.track_quality) {
    const CvtQuality q = cvt_quality(m_, V_.label, sites_);
    r_.mean_angle.push_back(q.mean_angle_deg);
    r_.min_angle.push_back(q.min_angle_deg);
  }
  std::vector<std::array<double, 3>> before(ns_);
  for (int32_t s = 0; s < ns_; ++s) before[s] = surface_point_position(m_, sites_[s]);
  // Centroids: batches of 8 cells in the sites' spatial order.
  const int32_t nbatch = (ns_ + kLanes - 1) / kLanes;
  CentroidSlots slots = centroid_slots(nbatch);
  psw.lap();
  // Reported batch by batch (~1 s at 416k vertices, 1,000 sites: a C host's chances to cancel).
  run_batch_graph<CentroidMsg>(
      step_context(it, 0.5, 1.0), nbatch, [&](int32_t b) { return solve_centroid_batch(b, before); },
      [&](const std::shared_ptr<CentroidMsg>& msg) { store(*msg, slots); }, "centroids");
  r_.centroids_s += psw.lap();
  r_.fallback_faces += slots.fallback;
  record_statistics(slots, nbatch);
  move_sites(slots, before);
  r_.iter_s.push_back(isw.lap());
  step_context(it, 0.0, 1.0).report(1.0, "lloyd");
}

// After the last iteration: the labels of the final sites, so that `label` and
// `sites` belong together, their split-triangle cell areas and the mean fractions.
void LloydLoop::finish() {
  ctx_.check_cancel();
  BatchStopwatch fsw;
  labels_ctx_ = ctx_.sub(static_cast<double>(std::max(1, opt_.iterations)) / (std::max(1, opt_.iterations) + 1.0), 1.0);
  labels_of_sites();
  r_.final_labels_s = fsw.lap();
  r_.label.assign(V_.label.begin(), V_.label.end());
  in_arena([&] {
    const HostVector<double> area = partition_cells(m_, in_.area_r3, V_, ns_).area;
    r_.cell_area.assign(area.begin(), area.end());
  });
  if (opt_.keep_voronoi) r_.voronoi = std::move(V_);
  r_.sites = std::move(sites_);
  if (read_batches_ > 0) {
    r_.centroid_read_fraction = centroid_read_sum_ / static_cast<double>(read_batches_);
    r_.label_read_fraction = label_read_sum_ / static_cast<double>(read_batches_);
  }
  r_.mean_kept_fraction = kept_fraction_.empty() ? 1.0
                                                 : std::accumulate(kept_fraction_.begin(), kept_fraction_.end(), 0.0) /
                                                       static_cast<double>(kept_fraction_.size());
}

}  // namespace

namespace {
LloydResult cvt_lloyd_impl(const Mesh& m, const MeshDerived* given, std::vector<SurfacePoint> sites,
                           const LloydOptions& opt, const RunContext& ctx);

// Random sites can miss a small component (whose vertices would then get no
// heat): each component without a site takes one from the component with the
// most sites (its last one), placed at the component's lowest vertex. Seeded
// draws stay as they were wherever every component was hit.
void give_every_component_a_site(const Mesh& m, const MeshDerived* given, std::vector<SurfacePoint>& sites) {
  std::vector<int32_t> own;
  const int32_t nc = given ? given->components : connected_components(m, own);
  if (nc <= 1) return;
  const int32_t* comp = given ? given->component.data() : own.data();
  if (static_cast<int32_t>(sites.size()) < nc)
    fail(ErrorCode::BadUsage, "cvt: " + std::to_string(sites.size()) + " sites for " + std::to_string(nc) +
                                  " connected components; every component needs at least one site");
  auto comp_of = [&](const SurfacePoint& p) {
    return comp[p.vertex >= 0 ? p.vertex : m.face_vertices[static_cast<size_t>(m.face_offsets[p.face])]];
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

LloydResult cvt_lloyd_random(const Mesh& m, const MeshDerived* given, const LloydOptions& opt, const RunContext& ctx) {
  if (opt.sites < 1) fail(ErrorCode::BadUsage, "cvt: at least one site");
  if (!m.is_triangle_mesh() || m.num_faces() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": cvt needs a triangle mesh");
  if (opt.sites > m.num_vertices())
    fail(ErrorCode::BadUsage, "cvt: " + std::to_string(opt.sites) + " sites but only " +
                                  std::to_string(m.num_vertices()) + " vertices (cells cannot be smaller than a vertex)");
  BatchStopwatch sw;
  std::vector<SurfacePoint> init = random_surface_points(m, opt.sites, opt.seed);
  give_every_component_a_site(m, given, init);
  const double seed_s = sw.lap();
  LloydResult r = cvt_lloyd_impl(m, given, std::move(init), opt, ctx);
  r.init_s += seed_s;
  return r;
}

LloydResult cvt_lloyd_impl(const Mesh& m, const MeshDerived* given, std::vector<SurfacePoint> sites,
                           const LloydOptions& opt, const RunContext& ctx) {
  const int32_t ns = static_cast<int32_t>(sites.size());
  MeshDerived own;
  const MeshDerived& derived = check_lloyd_input(m, given, sites, opt, own);
  const bool local = opt.solver == LloydOptions::Solver::Local;

  LloydResult r;
  BatchStopwatch sw;
  const HostVector<double> area_r3 = face_areas(m);
  // Progress: operators and first neighborhoods, then the iterations and the
  // final labels (LloydLoop), one monotone fraction. The first neighborhoods
  // cost ~1.3 iterations, the final labels about one (docs/shipping.md).
  const double init_share = 1.3 / (std::max(1, opt.iterations) + 2.3);
  const RunContext init_ctx = ctx.sub(0.0, init_share);
  LloydOperators ops;
  prepare_lloyd_operators(m, derived, opt, area_r3, sw, init_ctx.sub(0.0, 0.5), ops);
  const HeatDiffusion& H = *ops.H;
  const HeatDiffusion& Hc = *ops.Hc;
  sw.lap();
  r.factor_s = H.operator_s + H.order_s + H.analyze_s + H.factor_s + ops.Hc_own.factor_s;
  r.h = H.h;
  r.t = H.t;
  r.t_centroid = Hc.t;
  r.factor_bytes = static_cast<int64_t>((H.factor.values.size() + ops.Hc_own.factor.values.size()) * sizeof(double));
  ctx.check_cancel();
  // ~0.4 s at 416k vertices: the loops are cancel points (cancel_point.hpp).
  ProgressTicker geometry_ticker(init_ctx.sub(0.45, 0.5), "cvt geometry", 2.0);
  std::optional<CancelScope> scope(std::in_place, geometry_ticker);
  const CentroidGeometry geo = prepare_centroid_geometry(m, derived.adjacency);
  geometry_ticker.add(1.0);
  const Edges& edges = derived.incidence.edges;
  const VertexStars stars = vertex_stars(m, ops.area_op);
  geometry_ticker.add(1.0);
  ctx.check_cancel();
  const HostVector<double>& mass_r3 = derived.mass;
  const double h_r3 = derived.h;
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  // Reused per (thread, concurrency): an arena per call leaks inside oneTBB.
  const auto in_arena = [arena_threads = std::max(1, threads)](auto&& f) { run_with_threads(arena_threads, f); };

  // First neighborhoods: Dijkstra balls of the expected cell radius times init_radius.
  std::vector<std::vector<int32_t>> nb;
  HostVector<int32_t> first;  // init_cells: the sites' Dijkstra cells
  if (local && opt.init_cells) {
    first = dijkstra_cells(m, geo.adj, sites);
    if (std::find(first.begin(), first.end(), -1) != first.end()) first.clear();  // unreachable vertices: balls
  }
  if (local && first.empty()) {
    const HostVector<double>& mass3 = derived.mass;
    const double area = std::accumulate(mass3.begin(), mass3.end(), 0.0);
    const double radius = opt.init_radius * std::sqrt(area / (M_PI * ns));
    scope.reset();  // the neighborhoods below run on oneTBB workers
    in_arena([&] { nb = geodesic_neighborhoods(m, geo.adj, sites, radius, ctx); });
    ctx.check_cancel();
  }
  scope.reset();
  r.init_s = sw.lap();

  const RunContext loop_ctx = ctx.sub(init_share, 1.0);
  const LloydInputs in{m, opt, loop_ctx, H, Hc, geo, edges, stars, area_r3, mass_r3, h_r3, std::max(1, threads)};
  LloydLoop loop(in, sites, std::move(nb), r);
  if (!first.empty()) {
    loop.first_cells(first);
    r.init_s += sw.lap();
  }
  for (int32_t it = 0; it < opt.iterations; ++it) {
    loop.iterate(it);
    const std::vector<double>& e = r.energy;  // stopping rule (cvt_lloyd.hpp stop_energy)
    if (opt.stop_energy > 0 && e.size() >= 2 && e[e.size() - 2] - e.back() < opt.stop_energy * e.back()) break;
  }
  loop.finish();
  return r;
}

}  // namespace

std::vector<std::vector<int32_t>> geodesic_neighborhoods(const Mesh& m, const Adjacency& adj,
                                                         std::span<const SurfacePoint> sites, double radius,
                                                         const RunContext& ctx) {
  const int32_t ns = static_cast<int32_t>(sites.size());
  std::vector<std::vector<int32_t>> nb(ns);
  const HostVector<double> edge_length = adjacency_edge_lengths(m, adj);
  tbb::enumerable_thread_specific<GrowWorkspace> scratch;
  tbb::parallel_for(0, ns, [&](int32_t s) {
    if (!ctx.cancelled()) nb[s] = geodesic_ball(m, adj, edge_length, sites[s], radius, scratch.local());
  });
  ctx.check_cancel();
  return nb;
}

LloydResult cvt_lloyd(const Mesh& m, const LloydOptions& opt, const RunContext& ctx) {
  return cvt_lloyd_random(m, nullptr, opt, ctx);
}
LloydResult cvt_lloyd(const Mesh& m, const MeshDerived& d, const LloydOptions& opt, const RunContext& ctx) {
  return cvt_lloyd_random(m, &d, opt, ctx);
}
LloydResult cvt_lloyd(const Mesh& m, std::vector<SurfacePoint> sites, const LloydOptions& opt, const RunContext& ctx) {
  return cvt_lloyd_impl(m, nullptr, std::move(sites), opt, ctx);
}
LloydResult cvt_lloyd(const Mesh& m, const MeshDerived& d, std::vector<SurfacePoint> sites, const LloydOptions& opt,
                      const RunContext& ctx) {
  return cvt_lloyd_impl(m, &d, std::move(sites), opt, ctx);
}

}  // namespace locus
