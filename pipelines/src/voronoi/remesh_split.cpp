// Edge splits at the thinnest triangles of a remesh
// (pipelines/include/locus/pipelines/voronoi/remesh_split.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_split.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "remesh_vec3.hpp"

namespace locus {

int32_t split_thin(const TriangleGrid& grid, Mesh& remesh, double below_deg, int32_t budget,
                   std::vector<int32_t>& vertex_site, std::span<const uint8_t> pinned, bool boundary_edges) {
  using namespace remesh_vec3;
  const double below = below_deg * M_PI / 180;
  const int32_t nf = remesh.num_faces();
  std::vector<std::array<int32_t, 3>> F(nf);
  for (int32_t f = 0; f < nf; ++f) F[f] = {remesh.f0[f], remesh.f1[f], remesh.f2[f]};
  std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> ef;
  for (int32_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) ef[{std::min(F[f][k], F[f][(k + 1) % 3]), std::max(F[f][k], F[f][(k + 1) % 3])}].push_back(f);
  auto ang = [&](int32_t o, int32_t u, int32_t w) { return angle_at(pos(remesh, o), pos(remesh, u), pos(remesh, w)); };
  std::vector<std::pair<double, int32_t>> thin;
  for (int32_t f = 0; f < nf; ++f) {
    const double a = std::min({ang(F[f][0], F[f][1], F[f][2]), ang(F[f][1], F[f][2], F[f][0]), ang(F[f][2], F[f][0], F[f][1])});
    if (a < below) thin.push_back({a, f});
  }
  std::sort(thin.begin(), thin.end());
  std::vector<uint8_t> used(nf, 0);
  Mesh out = remesh;
  int32_t splits = 0;
  std::vector<std::array<int32_t, 3>> G = F;
  for (const auto& [a, f] : thin) {
    if (splits >= budget) break;
    if (used[f]) continue;
    int32_t best = 0;
    double len = -1;
    for (int k = 0; k < 3; ++k) {
      const double l = norm(sub(pos(remesh, F[f][k]), pos(remesh, F[f][(k + 1) % 3])));
      if (l > len) len = l, best = k;
    }
    const int32_t u = F[f][best], w = F[f][(best + 1) % 3];
    if (!pinned.empty() && pinned[u] && pinned[w]) continue;
    const auto& fs = ef[{std::min(u, w), std::max(u, w)}];
    if (!(fs.size() == 2 || (boundary_edges && fs.size() == 1))) continue;
    if (std::any_of(fs.begin(), fs.end(), [&](int32_t g) { return used[g] != 0; })) continue;
    const V3 pu = pos(remesh, u), pw = pos(remesh, w);
    const ClosestPoint cp = grid.closest({0.5 * (pu[0] + pw[0]), 0.5 * (pu[1] + pw[1]), 0.5 * (pu[2] + pw[2])});
    if (cp.face < 0) continue;
    const int32_t m = out.num_vertices();
    out.add_vertex(cp.point[0], cp.point[1], cp.point[2]);
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
  for (int32_t v = 0; v < out.num_vertices(); ++v) res.add_vertex(out.x[v], out.y[v], out.z[v]);
  for (const auto& t : G) res.add_triangle(t[0], t[1], t[2]);
  remesh = std::move(res);
  return splits;
}

}  // namespace locus
