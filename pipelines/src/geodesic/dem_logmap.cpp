// Discrete exponential map by Dijkstra propagation (pipelines/include/locus/pipelines/geodesic/dem_logmap.hpp).
#include "locus/pipelines/geodesic/dem_logmap.hpp"

#include "locus/kernels/mesh/index_min_heap.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

inline double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The shared index heap (locus/kernels/mesh/index_min_heap.hpp) on ws.dist, positions in ws.heap_pos.
inline void sift_up(DemWorkspace& ws, int32_t pos) { index_heap_sift_up(ws.heap, ws.dist.data(), ws.heap_pos.data(), pos); }
inline int32_t pop_min(DemWorkspace& ws) { return index_heap_pop_min(ws.heap, ws.dist.data(), ws.heap_pos.data()); }

}  // namespace

DemLogMap::DemLogMap(const Mesh& m) : x_(m.x), y_(m.y), z_(m.z) {
  validate_mesh_arrays(m);
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": the discrete exponential map needs triangles");
  for (int32_t i = 0; i < m.num_vertices(); ++i)
    if (!std::isfinite(m.x[i]) || !std::isfinite(m.y[i]) || !std::isfinite(m.z[i]))
      fail(ErrorCode::BadInput, mesh_name(m) + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
  normal_ = std::vector<double>(area_weighted_normals(m));
  const Adjacency a = vertex_adjacency(m);
  adj_offsets.assign(a.offsets.begin(), a.offsets.end());
  adj_.assign(a.neighbors.begin(), a.neighbors.end());
  len_.resize(adj_.size());
  for (int32_t i = 0; i < m.num_vertices(); ++i)
    for (int64_t q = adj_offsets[i]; q < adj_offsets[i + 1]; ++q) {
      const int32_t j = adj_[q];
      len_[q] = std::sqrt((x_[j] - x_[i]) * (x_[j] - x_[i]) + (y_[j] - y_[i]) * (y_[j] - y_[i]) +
                          (z_[j] - z_[i]) * (z_[j] - z_[i]));
    }
}

namespace {
void check_query(int32_t n, int32_t center, int32_t count, std::span<int32_t> patch, std::span<double> u,
                 std::span<double> v) {
  if (center < 0 || center >= n)
    fail(ErrorCode::BadUsage, "center " + std::to_string(center) + " is not a vertex (the mesh has " +
                                  std::to_string(n) + " vertices)");
  if (count < 1) fail(ErrorCode::BadUsage, "DEM: the patch needs at least one vertex");
  if (patch.size() < static_cast<size_t>(count))
    fail(ErrorCode::BadUsage, "DEM: patch output has " + std::to_string(patch.size()) + " entries, need " +
                                  std::to_string(count));
  const bool map = !u.empty() || !v.empty();
  if (map && (u.size() < static_cast<size_t>(count) || v.size() < static_cast<size_t>(count)))
    fail(ErrorCode::BadUsage, "DEM: u and v need at least " + std::to_string(count) + " entries");
}
}  // namespace

int32_t DemLogMap::query(int32_t center, int32_t count, double max_radius, std::span<int32_t> patch,
                         std::span<double> u, std::span<double> v, DemWorkspace& ws) const {
  check_query(num_vertices(), center, count, patch, u, v);
  const bool map = !u.empty() || !v.empty();
  begin_query(center, ws);
  int32_t k = 0;
  while (!ws.heap.empty() && k < count) {
    if (ws.dist[ws.heap[0]] > max_radius) break;
    const int32_t q = pop_min(ws);
    ws.state[q] = DemVertexState::Finalized;
    patch[k++] = q;
    if (map) {
      const int32_t p = ws.parent[q];
      if (p < 0) {
        center_frame(q, ws);
      } else {
        transport_frame(p, q, ws);
        average_coordinates(q, ws);
      }
      u[k - 1] = ws.u[q];
      v[k - 1] = ws.v[q];
    }
    relax(q, ws);
  }
  // Back to the between-queries state, at the entries this query touched only.
  for (int32_t t : ws.touched) {
    ws.dist[t] = std::numeric_limits<double>::infinity();
    ws.state[t] = DemVertexState::Unseen;
  }
  return k;
}

// Sizes the workspace for this mesh (once) and queues the center.
void DemLogMap::begin_query(int32_t center, DemWorkspace& ws) const {
  const int32_t n = num_vertices();
  if (ws.dist.size() != static_cast<size_t>(n)) {
    ws.dist.assign(n, std::numeric_limits<double>::infinity());
    ws.state.assign(n, DemVertexState::Unseen);
    ws.parent.assign(n, -1);
    ws.heap_pos.assign(n, -1);
    ws.u.assign(n, 0.0);
    ws.v.assign(n, 0.0);
    ws.e1.assign(3 * static_cast<size_t>(n), 0.0);
  }
  ws.heap.clear();
  ws.touched.clear();
  ws.dist[center] = 0.0;
  ws.state[center] = DemVertexState::Queued;
  ws.parent[center] = -1;
  ws.touched.push_back(center);
  ws.heap.push_back(center);
  ws.heap_pos[center] = 0;
}

// The center: coordinates (0, 0); reference direction = the edge to the
// lowest-numbered neighbor, projected into its tangent plane.
void DemLogMap::center_frame(int32_t q, DemWorkspace& ws) const {
  const double* nq = normal_.data() + 3 * static_cast<size_t>(q);
  double* e1q = ws.e1.data() + 3 * static_cast<size_t>(q);
  ws.u[q] = ws.v[q] = 0.0;
  if (adj_offsets[q + 1] > adj_offsets[q]) {
    const int32_t r = adj_[adj_offsets[q]];
    double d[3] = {x_[r] - x_[q], y_[r] - y_[q], z_[r] - z_[q]};
    const double dn = dot3(d, nq);
    for (int c = 0; c < 3; ++c) d[c] -= dn * nq[c];
    const double l = std::sqrt(dot3(d, d));
    for (int c = 0; c < 3; ++c) e1q[c] = l > 0 ? d[c] / l : 0.0;
  }
}

// q's frame: its parent p's e1 under the minimal rotation taking n_p to n_q,
// R e = e - (e . n_q) / (1 + n_p . n_q) (n_p + n_q) for e ⟂ n_p; then
// re-orthogonalized against n_q to keep rounding from accumulating.
void DemLogMap::transport_frame(int32_t p, int32_t q, DemWorkspace& ws) const {
  // Below this 1 + n_p . n_q the normals are antiparallel: no unique rotation.
  constexpr double kAntiparallel = 1e-12;
  const double* nq = normal_.data() + 3 * static_cast<size_t>(q);
  const double* np = normal_.data() + 3 * static_cast<size_t>(p);
  const double* e1p = ws.e1.data() + 3 * static_cast<size_t>(p);
  double* e1q = ws.e1.data() + 3 * static_cast<size_t>(q);
  const double c1 = 1.0 + dot3(np, nq);
  double e[3];
  if (c1 > kAntiparallel) {
    const double s = dot3(e1p, nq) / c1;
    for (int c = 0; c < 3; ++c) e[c] = e1p[c] - s * (np[c] + nq[c]);
  } else {
    for (int c = 0; c < 3; ++c) e[c] = e1p[c];
  }
  const double en = dot3(e, nq);
  for (int c = 0; c < 3; ++c) e[c] -= en * nq[c];
  const double l = std::sqrt(dot3(e, e));
  for (int c = 0; c < 3; ++c) e1q[c] = l > 0 ? e[c] / l : 0.0;
}

// q's coordinates: the average over its finalized neighbors r of
// u(r) + log_r(q), weighted by 1 / |q - r|.
void DemLogMap::average_coordinates(int32_t q, DemWorkspace& ws) const {
  double su = 0, sv = 0, sw = 0;
  for (int64_t a = adj_offsets[q]; a < adj_offsets[q + 1]; ++a) {
    const int32_t r = adj_[a];
    if (ws.state[r] != DemVertexState::Finalized || r == q) continue;
    const double* nr = normal_.data() + 3 * static_cast<size_t>(r);
    const double* er = ws.e1.data() + 3 * static_cast<size_t>(r);
    const double e2r[3] = {nr[1] * er[2] - nr[2] * er[1], nr[2] * er[0] - nr[0] * er[2],
                           nr[0] * er[1] - nr[1] * er[0]};
    double d[3] = {x_[q] - x_[r], y_[q] - y_[r], z_[q] - z_[r]};
    const double dn = dot3(d, nr);
    for (int c = 0; c < 3; ++c) d[c] -= dn * nr[c];
    const double pl = std::sqrt(dot3(d, d));
    const double len = len_[a];
    const double scale = pl > 0 ? len / pl : 0.0;
    const double w = 1.0 / len;
    su += w * (ws.u[r] + scale * dot3(d, er));
    sv += w * (ws.v[r] + scale * dot3(d, e2r));
    sw += w;
  }
  ws.u[q] = su / sw;
  ws.v[q] = sv / sw;
}

// Dijkstra's relaxation of q's edges: queues unseen neighbors, shortens queued ones.
void DemLogMap::relax(int32_t q, DemWorkspace& ws) const {
  const double dq = ws.dist[q];
  for (int64_t a = adj_offsets[q]; a < adj_offsets[q + 1]; ++a) {
    const int32_t r = adj_[a];
    if (ws.state[r] == DemVertexState::Finalized) continue;
    const double nd = dq + len_[a];
    if (ws.state[r] == DemVertexState::Unseen) {
      ws.state[r] = DemVertexState::Queued;
      ws.touched.push_back(r);
      ws.dist[r] = nd;
      ws.parent[r] = q;
      ws.heap.push_back(r);
      sift_up(ws, static_cast<int32_t>(ws.heap.size()) - 1);
    } else if (nd < ws.dist[r]) {
      ws.dist[r] = nd;
      ws.parent[r] = q;
      sift_up(ws, ws.heap_pos[r]);
    }
  }
}

}  // namespace locus
