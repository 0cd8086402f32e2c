// Edge splits at the thinnest triangles of a remesh
// (pipelines/include/locus/pipelines/voronoi/remesh_split.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_split.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <utility>

#include "remesh_vec3.hpp"

namespace locus {

namespace {

using namespace remesh_vec3;

using Tri = std::array<int32_t, 3>;

std::vector<Tri> triangles_of(const Mesh& remesh) {
  std::vector<Tri> F(static_cast<size_t>(remesh.num_faces()));
  for (int32_t f = 0; f < remesh.num_faces(); ++f) F[f] = {remesh.f0[f], remesh.f1[f], remesh.f2[f]};
  return F;
}

using EdgeFaces = std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>>;

EdgeFaces edge_faces(const std::vector<Tri>& F) {
  EdgeFaces ef;
  for (int32_t f = 0; f < static_cast<int32_t>(F.size()); ++f)
    for (int k = 0; k < 3; ++k)
      ef[{std::min(F[f][k], F[f][(k + 1) % 3]), std::max(F[f][k], F[f][(k + 1) % 3])}].push_back(f);
  return ef;
}

double edge_length(const Mesh& remesh, int32_t u, int32_t w) { return norm(sub(pos(remesh, u), pos(remesh, w))); }

// Splits the edges (u, w) in the given order, each at its midpoint projected
// onto the input, skipping an edge whose triangles were split already (so each
// split is one vertex and the same topology), an edge between two pinned
// vertices, and a boundary edge unless boundary_edges; at most budget splits.
// F and ef are remesh's triangles and edge_faces(F).
int32_t split_edges(const TriangleGrid& grid, Mesh& remesh, const std::vector<Tri>& F, const EdgeFaces& ef,
                    const std::vector<std::pair<int32_t, int32_t>>& order, int32_t budget,
                    std::vector<int32_t>& vertex_site, std::span<const uint8_t> pinned, bool boundary_edges) {
  std::vector<uint8_t> used(F.size(), 0);
  std::vector<V3> added;  // the new vertices, after remesh's
  std::vector<Tri> G = F;
  int32_t splits = 0;
  for (const auto& [u, w] : order) {
    if (splits >= budget) break;
    if (!pinned.empty() && pinned[u] && pinned[w]) continue;
    const auto& fs = ef.at({std::min(u, w), std::max(u, w)});
    if (!(fs.size() == 2 || (boundary_edges && fs.size() == 1))) continue;
    if (std::any_of(fs.begin(), fs.end(), [&](int32_t g) { return used[g] != 0; })) continue;
    const V3 pu = pos(remesh, u), pw = pos(remesh, w);
    const ClosestPoint cp = grid.closest({0.5 * (pu[0] + pw[0]), 0.5 * (pu[1] + pw[1]), 0.5 * (pu[2] + pw[2])});
    if (cp.face < 0) continue;
    const int32_t m = remesh.num_vertices() + static_cast<int32_t>(added.size());
    added.push_back(cp.point);
    if (!vertex_site.empty()) vertex_site.push_back(vertex_site[u]);
    for (int32_t g : fs) {
      used[g] = 1;
      int k = 0;
      while (!(G[g][k] == u && G[g][(k + 1) % 3] == w) && !(G[g][k] == w && G[g][(k + 1) % 3] == u)) ++k;
      const int32_t x = G[g][k], y = G[g][(k + 1) % 3], z = G[g][(k + 2) % 3];
      G[g] = {x, m, z};
      G.push_back({m, y, z});
    }
    ++splits;
  }
  if (splits == 0) return 0;
  Mesh res;
  for (int32_t v = 0; v < remesh.num_vertices(); ++v) res.add_vertex(remesh.x[v], remesh.y[v], remesh.z[v]);
  for (const V3& p : added) res.add_vertex(p[0], p[1], p[2]);
  for (const Tri& t : G) res.add_triangle(t[0], t[1], t[2]);
  remesh = std::move(res);
  return splits;
}

}  // namespace

int32_t split_thin(const TriangleGrid& grid, Mesh& remesh, double below_deg, int32_t budget,
                   std::vector<int32_t>& vertex_site, std::span<const uint8_t> pinned, bool boundary_edges) {
  const double below = below_deg * M_PI / 180;
  const std::vector<Tri> F = triangles_of(remesh);
  auto ang = [&](int32_t o, int32_t u, int32_t w) { return angle_at(pos(remesh, o), pos(remesh, u), pos(remesh, w)); };
  std::vector<std::pair<double, int32_t>> thin;
  for (int32_t f = 0; f < static_cast<int32_t>(F.size()); ++f) {
    const double a = std::min({ang(F[f][0], F[f][1], F[f][2]), ang(F[f][1], F[f][2], F[f][0]), ang(F[f][2], F[f][0], F[f][1])});
    if (a < below) thin.push_back({a, f});
  }
  std::sort(thin.begin(), thin.end());
  // Each thin triangle's longest edge, thinnest triangle first.
  std::vector<std::pair<int32_t, int32_t>> order;
  for (const auto& [a, f] : thin) {
    int32_t best = 0;
    double len = -1;
    for (int k = 0; k < 3; ++k) {
      const double l = edge_length(remesh, F[f][k], F[f][(k + 1) % 3]);
      if (l > len) len = l, best = k;
    }
    order.push_back({F[f][best], F[f][(best + 1) % 3]});
  }
  return split_edges(grid, remesh, F, edge_faces(F), order, budget, vertex_site, pinned, boundary_edges);
}

int32_t split_to_count(const TriangleGrid& grid, Mesh& remesh, int32_t target, std::vector<int32_t>& vertex_site,
                       std::span<const uint8_t> pinned) {
  int32_t total = 0;
  for (;;) {
    const int32_t need = target - remesh.num_vertices();
    if (need <= 0) break;
    // Longest first (ties by the vertex ids: the same order on every run).
    const std::vector<Tri> F = triangles_of(remesh);
    const EdgeFaces ef = edge_faces(F);
    std::vector<std::tuple<double, int32_t, int32_t>> edges;
    for (const auto& [e, fs] : ef) edges.push_back({-edge_length(remesh, e.first, e.second), e.first, e.second});
    std::sort(edges.begin(), edges.end());
    std::vector<std::pair<int32_t, int32_t>> order;
    for (const auto& [l, u, w] : edges) order.push_back({u, w});
    std::vector<uint8_t> pins(pinned.begin(), pinned.end());
    if (!pins.empty()) pins.resize(static_cast<size_t>(remesh.num_vertices()), 0);  // earlier passes' vertices move
    const int32_t s = split_edges(grid, remesh, F, ef, order, need, vertex_site, pins, true);
    if (s == 0) break;
    total += s;
  }
  return total;
}

}  // namespace locus
