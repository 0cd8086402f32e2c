// Surface points across one 1:4 midpoint subdivision
// (pipelines/include/locus/pipelines/voronoi/remesh_refinement.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_refinement.hpp"

#include <algorithm>
#include <array>
#include <string>

#include "locus/error.hpp"

namespace locus {

namespace {

// Barycentric weights over (a, b, d) of the corners of child k (the header's order).
constexpr double kChild[4][3][3] = {
    {{1, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}},
    {{0.5, 0.5, 0}, {0, 1, 0}, {0, 0.5, 0.5}},
    {{0.5, 0, 0.5}, {0, 0.5, 0.5}, {0, 0, 1}},
    {{0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}},
};

}  // namespace

std::vector<SurfacePoint> refine_surface_points(const Mesh& m, std::span<const SurfacePoint> p) {
  std::vector<SurfacePoint> out(p.begin(), p.end());
  for (SurfacePoint& q : out) {
    if (q.face < 0) continue;  // a vertex keeps its id
    if (q.face >= m.num_faces()) fail(ErrorCode::BadUsage, "refine surface points: face out of range");
    const double wa = q.bary[0], wb = q.bary[1], wd = q.bary[2];
    // The child holding the point; inverse of the child's corner weights.
    if (wa >= 0.5) {
      q.bary = {std::max(0.0, 1 - 2 * (wb + wd)), 2 * wb, 2 * wd};
      q.face = 4 * q.face;
    } else if (wb >= 0.5) {
      q.bary = {2 * wa, std::max(0.0, 1 - 2 * (wa + wd)), 2 * wd};
      q.face = 4 * q.face + 1;
    } else if (wd >= 0.5) {
      q.bary = {2 * wa, 2 * wb, std::max(0.0, 1 - 2 * (wa + wb))};
      q.face = 4 * q.face + 2;
    } else {
      q.bary = {1 - 2 * wd, 1 - 2 * wa, 1 - 2 * wb};
      q.face = 4 * q.face + 3;
    }
    const double s = q.bary[0] + q.bary[1] + q.bary[2];
    for (double& w : q.bary) w /= s;
  }
  return out;
}

std::vector<SurfacePoint> coarsen_surface_points(const Mesh& m, const Mesh& fine, std::span<const SurfacePoint> p) {
  if (fine.num_faces() != 4 * m.num_faces())
    fail(ErrorCode::BadUsage, "coarsen surface points: the fine mesh is not a 1:4 subdivision of m");
  const int32_t n = m.num_vertices();
  std::vector<SurfacePoint> out(p.begin(), p.end());
  // A midpoint vertex becomes a corner of one of its fine faces.
  std::vector<std::array<int32_t, 2>> corner_of(fine.num_vertices(), {-1, -1});
  for (int32_t f = 0; f < fine.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t v = fine.face(f)[k];
      if (v >= n && corner_of[v][0] < 0) corner_of[v] = {f, k};
    }
  for (SurfacePoint& q : out) {
    if (q.face < 0) {
      if (q.vertex < n) continue;
      if (q.vertex >= fine.num_vertices() || corner_of[q.vertex][0] < 0)
        fail(ErrorCode::BadUsage, "coarsen surface points: vertex " + std::to_string(q.vertex) + " out of range");
      const auto [f, k] = corner_of[q.vertex];
      q.face = f;
      q.bary = {0, 0, 0};
      q.bary[k] = 1;
    }
    const double(&w)[3][3] = kChild[q.face % 4];
    std::array<double, 3> b{0, 0, 0};
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) b[k] += q.bary[c] * w[c][k];
    q.face /= 4;
    q.vertex = -1;
    q.bary = b;
  }
  return out;
}

}  // namespace locus
