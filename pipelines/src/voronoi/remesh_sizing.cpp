// A sizing density from the curvature across edges
// (pipelines/include/locus/pipelines/voronoi/remesh_sizing.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_sizing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "locus/error.hpp"
#include "remesh_vec3.hpp"

namespace locus {

std::vector<double> sizing_density(const Mesh& m, double edge, double gain, double cap) {
  using namespace remesh_vec3;
  if (!(edge > 0) || !(gain >= 0) || !(cap >= 0)) fail(ErrorCode::BadUsage, "sizing density: edge > 0, gain and cap >= 0");
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  std::vector<double> curv(n, 0.0);
  if (gain > 0) {
    std::vector<V3> normal(nf);
    std::vector<double> area2(nf);
    for (int32_t f = 0; f < nf; ++f) {
      normal[f] = tri_normal(pos(m, m.f0[f]), pos(m, m.f1[f]), pos(m, m.f2[f]));
      area2[f] = norm(normal[f]);
    }
    std::unordered_map<uint64_t, int32_t> first;  // an edge's first face
    first.reserve(3 * static_cast<size_t>(nf));
    for (int32_t f = 0; f < nf; ++f) {
      const std::array<int32_t, 3> t = {m.f0[f], m.f1[f], m.f2[f]};
      for (int k = 0; k < 3; ++k) {
        const int32_t a = std::min(t[k], t[(k + 1) % 3]), b = std::max(t[k], t[(k + 1) % 3]);
        const uint64_t key = (static_cast<uint64_t>(a) << 32) | static_cast<uint32_t>(b);
        const auto [it, fresh] = first.try_emplace(key, f);
        if (fresh) continue;
        const int32_t g = it->second;
        const double len = norm(sub(pos(m, a), pos(m, b)));
        if (!(len > 0) || !(area2[f] > 0) || !(area2[g] > 0)) continue;
        const double theta = std::atan2(norm(cross(normal[f], normal[g])), dot(normal[f], normal[g]));
        // The mean height of the two triangles over the edge, at least e/8: a
        // crease bends at a point, whose curvature the remesh sees over an edge.
        const double width = std::max(0.25 * (area2[f] + area2[g]) / len, edge / 8);
        const double kv = std::min(theta / width, cap / edge);
        curv[a] = std::max(curv[a], kv);
        curv[b] = std::max(curv[b], kv);
      }
    }
    // Spread over one ring (the largest of the neighbors): a tube's vertices
    // between creases and the faces next to a small hole see it.
    std::vector<double> spread = curv;
    for (int32_t f = 0; f < nf; ++f) {
      const double k = std::max({curv[m.f0[f]], curv[m.f1[f]], curv[m.f2[f]]});
      for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) spread[v] = std::max(spread[v], k);
    }
    curv = std::move(spread);
  }
  std::vector<double> rho(n);
  for (int32_t v = 0; v < n; ++v) rho[v] = std::pow(1 + gain * std::min(edge * curv[v], cap), 4);
  return rho;
}

}  // namespace locus
