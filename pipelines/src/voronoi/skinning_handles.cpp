// Skinning handles as vertex sets: vertex lists and bones
// (pipelines/include/locus/pipelines/voronoi/skinning_handles.hpp; thesis §3.7.2).
#include "locus/pipelines/voronoi/skinning_handles.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

namespace {

int32_t nearest_vertex(const Mesh& m, const std::array<double, 3>& p) {
  int32_t best = -1;
  double bd = INFINITY;
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double dx = m.x[v] - p[0], dy = m.y[v] - p[1], dz = m.z[v] - p[2];
    const double d = dx * dx + dy * dy + dz * dz;
    if (d < bd) {
      bd = d;
      best = v;
    }
  }
  return best;
}

}  // namespace

std::vector<int32_t> bone_vertices(const Mesh& m, std::span<const std::array<double, 3>> bone) {
  if (bone.size() < 2) fail(ErrorCode::BadUsage, "bone: a polyline needs at least 2 points");
  for (const auto& p : bone)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      fail(ErrorCode::BadUsage, "bone: a point is not finite");
  if (m.num_vertices() == 0) fail(ErrorCode::BadUsage, "bone: the mesh has no vertex");
  const double step = 0.5 * mean_edge_length(m);
  std::vector<int32_t> out;
  for (size_t s = 0; s + 1 < bone.size(); ++s) {
    const auto& a = bone[s];
    const auto& b = bone[s + 1];
    const double len = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                 (b[2] - a[2]) * (b[2] - a[2]));
    const int64_t steps = step > 0 ? std::max<int64_t>(1, static_cast<int64_t>(std::ceil(len / step))) : 1;
    if (steps > 1000000) fail(ErrorCode::BadUsage, "bone: a segment is more than a million edge lengths long");
    for (int64_t i = 0; i <= steps; ++i) {
      const double t = static_cast<double>(i) / static_cast<double>(steps);
      out.push_back(nearest_vertex(m, {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])}));
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<std::vector<int32_t>> handle_vertex_sets(const Mesh& m, std::span<const SkinningHandle> handles) {
  const int32_t n = m.num_vertices();
  if (handles.empty()) fail(ErrorCode::BadUsage, "skinning handles: no handle given");
  std::vector<int32_t> owner(n, -1);
  std::vector<std::vector<int32_t>> sets(handles.size());
  for (size_t i = 0; i < handles.size(); ++i) {
    const std::string name = "skinning handle " + std::to_string(i);
    const bool is_bone = handles[i].vertices.empty();
    std::vector<int32_t> set = is_bone ? bone_vertices(m, handles[i].bone) : handles[i].vertices;
    if (set.empty()) fail(ErrorCode::BadUsage, name + ": no vertex and no bone");
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    for (int32_t v : set) {
      if (v < 0 || v >= n)
        fail(ErrorCode::BadUsage, name + ": vertex " + std::to_string(v) + " out of range (the mesh has " +
                                      std::to_string(n) + " vertices)");
      if (owner[v] >= 0 && !is_bone)
        fail(ErrorCode::BadUsage, name + ": vertex " + std::to_string(v) + " is also in skinning handle " +
                                      std::to_string(owner[v]));
    }
    for (int32_t v : set)
      if (owner[v] < 0) {
        owner[v] = static_cast<int32_t>(i);
        sets[i].push_back(v);
      }
    if (sets[i].empty()) fail(ErrorCode::BadUsage, name + ": every vertex of the bone belongs to earlier handles");
  }
  return sets;
}

}  // namespace locus
