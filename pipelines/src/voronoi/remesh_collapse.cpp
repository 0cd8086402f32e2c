// Edge collapses to the requested vertex count
// (pipelines/include/locus/pipelines/voronoi/remesh_collapse.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_collapse.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "remesh_vec3.hpp"

namespace locus {

namespace {

using namespace remesh_vec3;

struct Work {
  std::vector<V3> p;
  std::vector<std::array<int32_t, 3>> F;
  std::vector<uint8_t> face_alive, vert_alive, boundary;
  std::span<const uint8_t> pinned;       // per vertex, or empty
  std::vector<std::vector<int32_t>> vf;  // per vertex: its faces (dead ones dropped lazily)
  std::vector<int32_t> loop, loop_size;   // per boundary vertex: its loop; per loop: its vertices

  std::vector<int32_t> faces_of(int32_t v) const {
    std::vector<int32_t> out;
    for (int32_t f : vf[v])
      if (face_alive[f]) out.push_back(f);
    return out;
  }
  std::vector<int32_t> neighbors(int32_t v) const {
    std::vector<int32_t> out;
    for (int32_t f : faces_of(v))
      for (int32_t w : F[f])
        if (w != v) out.push_back(w);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
};

// How far the boundary turns at boundary vertex v (its two boundary
// neighbors a, b): the merged vertex of a boundary edge stays at the endpoint
// that turns more (a corner of the loop keeps its place).
double turning(const Work& W, int32_t v, const std::vector<int32_t>& nb) {
  std::vector<int32_t> ends;
  for (int32_t w : nb)
    if (W.boundary[w]) {
      int faces = 0;
      for (int32_t f : W.faces_of(v))
        faces += std::find(W.F[f].begin(), W.F[f].end(), w) != W.F[f].end();
      if (faces == 1) ends.push_back(w);
    }
  if (ends.size() != 2) return M_PI;
  const V3 a = sub(W.p[v], W.p[ends[0]]), b = sub(W.p[ends[1]], W.p[v]);
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

// Collapses u-w when the conditions of the header hold; `touched` gets the
// vertices whose neighborhood changed.
bool try_collapse(const Mesh& input, const TriangleGrid& grid, Work& W, int32_t u, int32_t w,
                  std::vector<int32_t>& touched, double floor_rad) {
  const std::vector<int32_t> fu = W.faces_of(u), fw = W.faces_of(w);
  std::vector<int32_t> shared;
  for (int32_t f : fu)
    if (std::find(fw.begin(), fw.end(), f) != fw.end()) shared.push_back(f);
  const bool edge_on_boundary = shared.size() == 1;
  if (shared.empty() || shared.size() > 2) return false;
  if (W.boundary[u] && W.boundary[w] && !edge_on_boundary) return false;  // would pinch
  if (edge_on_boundary && W.loop_size[W.loop[u]] <= 3) return false;
  const std::vector<int32_t> nu = W.neighbors(u), nw = W.neighbors(w);
  std::vector<int32_t> common;
  std::set_intersection(nu.begin(), nu.end(), nw.begin(), nw.end(), std::back_inserter(common));
  if (common.size() != shared.size()) return false;  // the link condition
  for (int32_t c : common)
    if (W.neighbors(c).size() <= 3) return false;
  // Where the kept vertex goes: the projected midpoint inside, the boundary
  // endpoint when one is on the boundary.
  int32_t keep = u, drop = w;
  V3 target;
  const bool pin_u = !W.pinned.empty() && W.pinned[u], pin_w = !W.pinned.empty() && W.pinned[w];
  if ((pin_u && pin_w) || ((pin_u || pin_w) && (W.boundary[u] || W.boundary[w]))) return false;
  if (pin_u || pin_w) {  // the free vertex goes into the pinned one
    if (pin_w) std::swap(keep, drop);
    target = W.p[keep];
  } else if (edge_on_boundary) {
    const double tu = turning(W, u, nu), tw = turning(W, w, nw);
    if (tw > tu) std::swap(keep, drop);
    // Flat: only a vertex where the loop runs straight goes (its curve stays).
    if (floor_rad > 0 && std::min(tu, tw) > 10 * M_PI / 180) return false;
    target = W.p[keep];
  } else if (W.boundary[u] || W.boundary[w]) {
    if (W.boundary[w]) std::swap(keep, drop);
    target = W.p[keep];
  } else {
    const V3 mid = {0.5 * (W.p[u][0] + W.p[w][0]), 0.5 * (W.p[u][1] + W.p[w][1]), 0.5 * (W.p[u][2] + W.p[w][2])};
    const ClosestPoint cp = grid.closest(mid);
    if (cp.face < 0) return false;
    V3 ring{0, 0, 0};
    for (int32_t f : fu) {
      const V3 n = tri_normal(W.p[W.F[f][0]], W.p[W.F[f][1]], W.p[W.F[f][2]]);
      for (int k = 0; k < 3; ++k) ring[k] += n[k];
    }
    const auto fv = input.face(cp.face);
    const V3 ni = tri_normal(pos(input, fv[0]), pos(input, fv[1]), pos(input, fv[2]));
    if (!(dot(ni, ring) > 0.5 * norm(ni) * norm(ring))) return false;
    target = cp.point;
  }
  std::vector<int32_t> moved = fu;
  moved.insert(moved.end(), fw.begin(), fw.end());
  for (int32_t f : moved) {  // no remaining triangle turns more than 60 degrees
    if (std::find(shared.begin(), shared.end(), f) != shared.end()) continue;
    std::array<V3, 3> a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = W.p[W.F[f][k]];
      b[k] = W.F[f][k] == u || W.F[f][k] == w ? target : a[k];
    }
    const V3 n0 = tri_normal(a[0], a[1], a[2]), n1 = tri_normal(b[0], b[1], b[2]);
    if (!(dot(n0, n1) > 0.5 * norm(n0) * norm(n1))) return false;
    if (floor_rad > 0 && !(min_angle(b[0], b[1], b[2]) >= floor_rad)) return false;
  }
  for (int32_t f : shared) W.face_alive[f] = 0;
  for (int32_t f : drop == w ? fw : fu)
    if (W.face_alive[f]) {
      for (int32_t& x : W.F[f])
        if (x == drop) x = keep;
      W.vf[keep].push_back(f);
    }
  if (edge_on_boundary) --W.loop_size[W.loop[u]];
  W.vert_alive[drop] = 0;
  W.p[keep] = target;
  touched = nu;
  touched.insert(touched.end(), nw.begin(), nw.end());
  touched.push_back(u);
  touched.push_back(w);
  return true;
}

// Per vertex, in degrees: the largest angle between one of its triangles'
// normals and their area-weighted sum (0 on a plane).
std::vector<double> ring_bend(const Work& W) {
  const size_t n = W.p.size();
  std::vector<V3> sum(n, V3{0, 0, 0});
  for (size_t f = 0; f < W.F.size(); ++f)
    if (W.face_alive[f]) {
      const V3 t = tri_normal(W.p[W.F[f][0]], W.p[W.F[f][1]], W.p[W.F[f][2]]);
      for (int32_t v : W.F[f])
        for (int k = 0; k < 3; ++k) sum[v][k] += t[k];
    }
  std::vector<double> bend(n, 0.0);
  for (size_t f = 0; f < W.F.size(); ++f)
    if (W.face_alive[f]) {
      const V3 t = tri_normal(W.p[W.F[f][0]], W.p[W.F[f][1]], W.p[W.F[f][2]]);
      for (int32_t v : W.F[f])
        bend[v] = std::max(bend[v], std::atan2(norm(cross(t, sum[v])), dot(t, sum[v])) * 180 / M_PI);
    }
  return bend;
}

}  // namespace

int32_t collapse_to_count(const Mesh& input, const TriangleGrid& grid, Mesh& remesh, int32_t target,
                          std::vector<int32_t>& vertex_site, std::span<const uint8_t> pinned, CollapseOrder order) {
  const int32_t n = remesh.num_vertices();
  if (n <= target) return 0;
  if (!pinned.empty() && pinned.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "collapse remesh: pinned must have one entry per vertex");
  Work W;
  W.p.resize(n);
  for (int32_t v = 0; v < n; ++v) W.p[v] = pos(remesh, v);
  W.F.resize(remesh.num_faces());
  for (int32_t f = 0; f < remesh.num_faces(); ++f) W.F[f] = {remesh.f0[f], remesh.f1[f], remesh.f2[f]};
  W.face_alive.assign(W.F.size(), 1);
  W.vert_alive.assign(n, 1);
  W.boundary.assign(n, 0);
  W.pinned = pinned;
  W.vf.resize(n);
  std::map<std::pair<int32_t, int32_t>, int32_t> edge_faces;
  for (int32_t f = 0; f < static_cast<int32_t>(W.F.size()); ++f)
    for (int k = 0; k < 3; ++k) {
      W.vf[W.F[f][k]].push_back(f);
      const int32_t a = W.F[f][k], b = W.F[f][(k + 1) % 3];
      ++edge_faces[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [e, c] : edge_faces)
    if (c != 2) W.boundary[e.first] = W.boundary[e.second] = 1;
  W.loop.assign(n, -1);
  for (const std::vector<int32_t>& l : boundary_loops(remesh)) {
    for (int32_t v : l) W.loop[v] = static_cast<int32_t>(W.loop_size.size());
    W.loop_size.push_back(static_cast<int32_t>(l.size()));
  }
  int32_t alive = n, collapses = 0;
  for (bool any = true; any && alive > target;) {
    any = false;
    // Each vertex's mean edge: an edge short against its surroundings goes
    // first (the crowd of repair sites), not the shortest of a graded region.
    std::vector<double> mean_edge(n, 0.0);
    std::vector<int32_t> deg(n, 0);
    for (int32_t f = 0; f < static_cast<int32_t>(W.F.size()); ++f)
      if (W.face_alive[f])
        for (int k = 0; k < 3; ++k) {
          const int32_t a = W.F[f][k], b = W.F[f][(k + 1) % 3];
          const double l = norm(sub(W.p[a], W.p[b]));
          mean_edge[a] += l, ++deg[a];
          mean_edge[b] += l, ++deg[b];
        }
    const std::vector<double> bend = order == CollapseOrder::Flat ? ring_bend(W) : std::vector<double>{};
    std::vector<std::pair<double, std::pair<int32_t, int32_t>>> edges;
    for (int32_t f = 0; f < static_cast<int32_t>(W.F.size()); ++f)
      if (W.face_alive[f])
        for (int k = 0; k < 3; ++k) {
          const int32_t a = W.F[f][k], b = W.F[f][(k + 1) % 3];
          if (a >= b) continue;
          const double rel = norm(sub(W.p[a], W.p[b])) * (deg[a] + deg[b]) / (mean_edge[a] + mean_edge[b]);
          // Flat: whole degrees of bend first (flat regions), then the shortest.
          edges.push_back({bend.empty() ? rel : std::floor(std::max(bend[a], bend[b])) + 0.5 * std::min(rel, 1.9), {a, b}});
        }
    std::sort(edges.begin(), edges.end());
    std::vector<uint8_t> locked(n, 0);  // one collapse per neighborhood and pass
    std::vector<int32_t> touched;
    for (const auto& [len, e] : edges) {
      if (alive <= target) break;
      const auto [a, b] = e;
      if (locked[a] || locked[b] || !W.vert_alive[a] || !W.vert_alive[b]) continue;
      if (!try_collapse(input, grid, W, a, b, touched, order == CollapseOrder::Flat ? 20 * M_PI / 180 : 0)) continue;
      for (int32_t v : touched) locked[v] = 1;
      --alive;
      ++collapses;
      any = true;
    }
  }
  if (collapses == 0) return 0;
  std::vector<int32_t> id(n, -1);
  Mesh out;
  std::vector<int32_t> site;
  for (int32_t v = 0; v < n; ++v)
    if (W.vert_alive[v]) {
      id[v] = out.num_vertices();
      out.add_vertex(W.p[v][0], W.p[v][1], W.p[v][2]);
      if (!vertex_site.empty()) site.push_back(vertex_site[v]);
    }
  for (int32_t f = 0; f < static_cast<int32_t>(W.F.size()); ++f)
    if (W.face_alive[f]) out.add_triangle(id[W.F[f][0]], id[W.F[f][1]], id[W.F[f][2]]);
  remesh = std::move(out);
  if (!vertex_site.empty()) vertex_site = std::move(site);
  return collapses;
}

}  // namespace locus
