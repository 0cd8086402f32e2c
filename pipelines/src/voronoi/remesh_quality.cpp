// Topology, angles and Hausdorff distance of a remesh
// (pipelines/include/locus/pipelines/voronoi/remesh_quality.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_quality.hpp"

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>
#include <oneapi/tbb/blocked_range.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <utility>
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

namespace {

// The distance to a surface is 1-Lipschitz, and every point of a triangle
// lies within its longest edge / sqrt(3) of a corner (the circumradius of
// an acute triangle, half the longest edge of an obtuse one). So a triangle
// whose corners' distances plus that reach stay below the largest distance
// found (within kTol, or kAbsTol of the meshes' size) holds no point
// farther; the others are split at their edge midpoints, depth first. When
// its three corners are nearest to one target triangle, their mean point on
// it is within the corners' largest distance of any point of the triangle
// (convexity), so the corners give its largest distance. The answer is the
// largest distance met: a lower bound, within kTol of the true distance
// unless a face reaches kMaxSplits (~4,000 midpoint queries).
constexpr double kTol = 0.01, kAbsTol = 1e-7;
constexpr int kMaxSplits = 1365;  // 4^0 + ... + 4^5 sub-triangles

struct SubTriangle {
  V3 p[3];
  double d[3];
  int32_t f[3];  // each corner's nearest target face
};

double reach(const V3& a, const V3& b, const V3& c) {
  const double l2 = std::max({dot(sub(a, b), sub(a, b)), dot(sub(b, c), sub(b, c)), dot(sub(c, a), sub(c, a))});
  return std::sqrt(l2 / 3);
}

V3 mid(const V3& a, const V3& b) { return {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])}; }

struct Target {
  const Mesh& mesh;
  const TriangleGrid& grid;
  double abs_tol;
  bool triangle(int32_t f) const { return f >= 0 && mesh.face(f).size() == 3; }
};

double top_of(const SubTriangle& t) { return std::max({t.d[0], t.d[1], t.d[2]}); }

// Nothing in t can be farther than `best` (within the tolerances): its corners
// are nearest one target triangle, or their distances plus its reach stay below.
bool settled(const Target& tg, const SubTriangle& t, double best) {
  if (t.f[0] == t.f[1] && t.f[1] == t.f[2] && tg.triangle(t.f[0])) return true;
  return top_of(t) + reach(t.p[0], t.p[1], t.p[2]) <= std::max(best * (1 + kTol), best + tg.abs_tol);
}

// The largest distance from triangle `root` to the target above `floor` (else
// `floor`): a search of its own, so the thread count does not change it.
double face_search(const Target& tg, const SubTriangle& root, double floor) {
  double best = floor;
  std::vector<SubTriangle> stack{root};
  for (int splits = 0; !stack.empty();) {
    const SubTriangle t = stack.back();
    stack.pop_back();
    best = std::max(best, top_of(t));
    if (settled(tg, t, best) || ++splits > kMaxSplits) continue;
    const V3 m[3] = {mid(t.p[0], t.p[1]), mid(t.p[1], t.p[2]), mid(t.p[2], t.p[0])};
    ClosestPoint c[3];
    for (int k = 0; k < 3; ++k) c[k] = tg.grid.closest(m[k]);
    const double dm[3] = {c[0].distance, c[1].distance, c[2].distance};
    const int32_t fm[3] = {c[0].face, c[1].face, c[2].face};
    stack.push_back({{t.p[0], m[0], m[2]}, {t.d[0], dm[0], dm[2]}, {t.f[0], fm[0], fm[2]}});
    stack.push_back({{m[0], t.p[1], m[1]}, {dm[0], t.d[1], dm[1]}, {fm[0], t.f[1], fm[1]}});
    stack.push_back({{m[2], m[1], t.p[2]}, {dm[2], dm[1], t.d[2]}, {fm[2], fm[1], t.f[2]}});
    stack.push_back({{m[0], m[1], m[2]}, {dm[0], dm[1], dm[2]}, {fm[0], fm[1], fm[2]}});
  }
  return best;
}

double face_max(const Target& tg, const SubTriangle& root, double floor) {
  // Most faces end at the root: no stack for them.
  const double best = std::max(floor, top_of(root));
  return settled(tg, root, best) ? best : face_search(tg, root, floor);
}

// Every vertex of `src` to the target: distance and nearest face.
void vertex_distances(const Mesh& src, const TriangleGrid& g, std::vector<double>& d, std::vector<int32_t>& f) {
  d.resize(static_cast<size_t>(src.num_vertices()));
  f.resize(d.size());
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, src.num_vertices()), [&](const tbb::blocked_range<int32_t>& r) {
    for (int32_t v = r.begin(); v < r.end(); ++v) {
      const ClosestPoint c = g.closest(pos(src, v));
      d[static_cast<size_t>(v)] = c.distance;
      f[static_cast<size_t>(v)] = c.face;
    }
  });
}

// The faces of `src` (polygons as fans) searched against the target, above `floor`.
double faces_max(const Mesh& src, const std::vector<double>& dv, const std::vector<int32_t>& near,
                 const Target& tg, double floor) {
  return max_over(src.num_faces(), [&](int64_t f) {
    const auto fv = src.face(static_cast<int32_t>(f));
    double best = floor;
    for (size_t t = 1; t + 1 < fv.size(); ++t) {
      const int32_t i[3] = {fv[0], fv[t], fv[t + 1]};
      const SubTriangle root{{pos(src, i[0]), pos(src, i[1]), pos(src, i[2])},
                             {dv[i[0]], dv[i[1]], dv[i[2]]},
                             {near[i[0]], near[i[1]], near[i[2]]}};
      best = std::max(best, face_max(tg, root, floor));
    }
    return best;
  });
}

}  // namespace

double hausdorff_distance(const Mesh& a, const TriangleGrid& ga, const Mesh& b) {
  if (a.num_faces() == 0 || b.num_faces() == 0) fail(ErrorCode::BadUsage, "hausdorff: both meshes need faces");
  const TriangleGrid gb(b);
  // Vertices first: their largest distance is the floor every face search starts from.
  std::vector<double> da, db;
  std::vector<int32_t> near_a, near_b;  // per vertex of a (of b): its nearest face of b (of a)
  vertex_distances(a, gb, da, near_a);
  vertex_distances(b, ga, db, near_b);
  // The floor over the faces' corners: an unreferenced vertex is not on the surface.
  double floor = 0;
  for (const auto& [m, d] : {std::pair{&a, &da}, std::pair{&b, &db}})
    for (int32_t f = 0; f < m->num_faces(); ++f)
      for (int32_t v : m->face(f)) floor = std::max(floor, (*d)[static_cast<size_t>(v)]);
  const double abs_tol = kAbsTol * bounding_box_diagonal(a);
  // A floor fixed before the parallel searches keeps the answer the same on any thread count.
  const double ab = faces_max(a, da, near_a, Target{b, gb, abs_tol}, floor);
  return std::max(ab, faces_max(b, db, near_b, Target{a, ga, abs_tol}, floor));
}

double sampled_hausdorff_distance(const Mesh& input, const TriangleGrid& grid, const Mesh& remesh) {
  const TriangleGrid rg(remesh);
  static constexpr double kSamples[][3] = {{0.5, 0.5, 0},           {0, 0.5, 0.5},           {0.5, 0, 0.5},
                                           {4 / 6., 1 / 6., 1 / 6.}, {1 / 6., 4 / 6., 1 / 6.}, {1 / 6., 1 / 6., 4 / 6.},
                                           {1 / 3., 1 / 3., 1 / 3.}};
  const double to_remesh =
      max_over(input.num_vertices(), [&](int64_t v) { return rg.distance(pos(input, static_cast<int32_t>(v))); });
  const double to_input = max_over(remesh.num_faces(), [&](int64_t f) {
    const V3 p0 = pos(remesh, remesh.f0[f]), p1 = pos(remesh, remesh.f1[f]), p2 = pos(remesh, remesh.f2[f]);
    double d = 0;
    for (const auto& w : kSamples)
      d = std::max(d, grid.distance({w[0] * p0[0] + w[1] * p1[0] + w[2] * p2[0], w[0] * p0[1] + w[1] * p1[1] + w[2] * p2[1],
                                     w[0] * p0[2] + w[1] * p1[2] + w[2] * p2[2]}));
    return d;
  });
  const double vertices =
      max_over(remesh.num_vertices(), [&](int64_t v) { return grid.distance(pos(remesh, static_cast<int32_t>(v))); });
  return std::max({to_remesh, to_input, vertices});
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
