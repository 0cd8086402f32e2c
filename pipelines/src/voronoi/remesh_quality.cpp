// Topology, angles and Hausdorff distance of a remesh
// (pipelines/include/locus/pipelines/voronoi/remesh_quality.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_quality.hpp"

#include <oneapi/tbb/parallel_reduce.h>
#include <oneapi/tbb/blocked_range.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"
#include "remesh_vec3.hpp"

namespace locus {

namespace {

using namespace remesh_vec3;


double max_over(int64_t count, const std::function<double(int64_t)>& f) {
  return tbb::parallel_reduce(
      tbb::blocked_range<int64_t>(0, count), 0.0,
      [&](const tbb::blocked_range<int64_t>& r, double acc) {
        for (int64_t i = r.begin(); i < r.end(); ++i) acc = std::max(acc, f(i));
        return acc;
      },
      [](double a, double b) { return std::max(a, b); });
}

double smallest_angle_deg(const V3& a, const V3& b, const V3& c) {
  const V3* p[3] = {&a, &b, &c};
  double best = 180;
  for (int k = 0; k < 3; ++k) {
    const V3 d1 = sub(*p[(k + 1) % 3], *p[k]), d2 = sub(*p[(k + 2) % 3], *p[k]);
    const V3 x = {d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2], d1[0] * d2[1] - d1[1] * d2[0]};
    best = std::min(best, std::atan2(std::sqrt(dot(x, x)), dot(d1, d2)) * 180.0 / M_PI);
  }
  return best;
}

// The input's bounding-box diagonal (the scale of hausdorff_rel): the box of
// every vertex, as analyze_mesh reports it, without the rest of its report.
double bounding_box_diagonal(const Mesh& m) {
  if (m.num_vertices() == 0) return 0;
  double diag2 = 0;
  for (const auto* c : {&m.x, &m.y, &m.z}) {
    const auto [lo, hi] = std::minmax_element(c->begin(), c->end());
    diag2 += (*hi - *lo) * (*hi - *lo);
  }
  return std::sqrt(diag2);
}

}  // namespace

double hausdorff_distance(const Mesh& a, const Mesh& b) {
  if (a.num_faces() == 0 || b.num_faces() == 0) fail(ErrorCode::BadUsage, "hausdorff: both meshes need faces");
  return hausdorff_distance(a, TriangleGrid(a), b);
}

double hausdorff_distance(const Mesh& a, const TriangleGrid& ga, const Mesh& b) {
  if (a.num_faces() == 0 || b.num_faces() == 0) fail(ErrorCode::BadUsage, "hausdorff: both meshes need faces");
  const TriangleGrid gb(b);
  // Vertices of a to b (max is order-independent, so the reduction is deterministic).
  const double ab = max_over(a.num_vertices(), [&](int64_t v) { return gb.distance(pos(a, static_cast<int32_t>(v))); });
  static constexpr double kSamples[][3] = {{0.5, 0.5, 0},       {0, 0.5, 0.5},       {0.5, 0, 0.5},
                                           {4 / 6., 1 / 6., 1 / 6.}, {1 / 6., 4 / 6., 1 / 6.}, {1 / 6., 1 / 6., 4 / 6.},
                                           {1 / 3., 1 / 3., 1 / 3.}};
  auto samples_to = [&](const Mesh& src, const TriangleGrid& g) {
    return max_over(src.num_faces(), [&](int64_t f) {
      const auto fv = src.face(static_cast<int32_t>(f));
      double d = g.distance(pos(src, fv[0]));
      for (size_t t = 1; t + 1 < fv.size(); ++t) {
        const V3 p0 = pos(src, fv[0]), p1 = pos(src, fv[t]), p2 = pos(src, fv[t + 1]);
        for (const auto& w : kSamples)
          d = std::max(d, g.distance({w[0] * p0[0] + w[1] * p1[0] + w[2] * p2[0], w[0] * p0[1] + w[1] * p1[1] + w[2] * p2[1],
                                      w[0] * p0[2] + w[1] * p1[2] + w[2] * p2[2]}));
      }
      return d;
    });
  };
  const double ba = std::max(max_over(b.num_vertices(), [&](int64_t v) { return ga.distance(pos(b, static_cast<int32_t>(v))); }),
                             samples_to(b, ga));
  return std::max(ab, ba);
}

RemeshStats mesh_topology_stats(const Mesh& m) { return mesh_topology_stats(m, analyze_mesh(m)); }

RemeshStats mesh_topology_stats(const Mesh& m, const MeshReport& rep) {
  RemeshStats s;
  s.vertices = m.num_vertices();
  s.faces = m.num_faces();
  s.manifold = rep.manifold && rep.unreferenced_vertices == 0;
  s.components = rep.components;
  s.boundary_loops = rep.boundary_loops;
  s.euler_characteristic = rep.euler_characteristic;
  const int64_t twice = 2 * static_cast<int64_t>(rep.components) - rep.euler_characteristic - rep.boundary_loops;
  s.genus = s.manifold && twice >= 0 && twice % 2 == 0 ? twice / 2 : -1;
  return s;
}

namespace {

RemeshStats remesh_stats_with(const Mesh& input, const TriangleGrid* grid, const Mesh& remesh, bool hausdorff) {
  RemeshStats s = mesh_topology_stats(remesh);
  double sum = 0, mn = 180;
  int64_t below = 0, tris = 0;
  for (int32_t f = 0; f < remesh.num_faces(); ++f) {
    const auto fv = remesh.face(f);
    for (size_t t = 1; t + 1 < fv.size(); ++t) {
      const double a = smallest_angle_deg(pos(remesh, fv[0]), pos(remesh, fv[t]), pos(remesh, fv[t + 1]));
      sum += a;
      mn = std::min(mn, a);
      below += a < 30;
      ++tris;
    }
  }
  s.mean_min_angle_deg = tris ? sum / static_cast<double>(tris) : 0.0;
  s.min_angle_deg = tris ? mn : 0.0;
  s.pct_below_30_deg = tris ? 100.0 * static_cast<double>(below) / static_cast<double>(tris) : 0.0;
  if (hausdorff && tris > 0) {
    const double diag = bounding_box_diagonal(input);
    const double d = grid ? hausdorff_distance(input, *grid, remesh) : hausdorff_distance(input, remesh);
    s.hausdorff_rel = diag > 0 ? d / diag : 0.0;
  }
  return s;
}

}  // namespace

RemeshStats remesh_stats(const Mesh& input, const Mesh& remesh, bool hausdorff) {
  return remesh_stats_with(input, nullptr, remesh, hausdorff);
}

RemeshStats remesh_stats(const Mesh& input, const TriangleGrid& input_grid, const Mesh& remesh) {
  return remesh_stats_with(input, &input_grid, remesh, true);
}

}  // namespace locus
