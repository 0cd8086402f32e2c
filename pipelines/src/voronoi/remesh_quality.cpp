// Topology, angles and Hausdorff distance of a remesh
// (pipelines/include/locus/pipelines/voronoi/remesh_quality.hpp; issue 23).
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

namespace locus {

namespace {

using V3 = std::array<double, 3>;

V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 pos(const Mesh& m, int32_t v) { return {m.x[v], m.y[v], m.z[v]}; }

// Squared distance from p to triangle abc (closest point by Voronoi regions of
// the triangle's features, Ericson "Real-Time Collision Detection" §5.1.5).
double point_triangle_dist2(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  auto d2 = [&](const V3& q) {
    const V3 d = sub(p, q);
    return dot(d, d);
  };
  const double d1 = dot(ab, ap), d2v = dot(ac, ap);
  if (d1 <= 0 && d2v <= 0) return d2(a);
  const V3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return d2(b);
  const double vc = d1 * d4 - d3 * d2v;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return d2({a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2]});
  }
  const V3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return d2(c);
  const double vb = d5 * d2v - d1 * d6;
  if (vb <= 0 && d2v >= 0 && d6 <= 0) {
    const double w = d2v / (d2v - d6);
    return d2({a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2]});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return d2({b[0] + w * (c[0] - b[0]), b[1] + w * (c[1] - b[1]), b[2] + w * (c[2] - b[2])});
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return d2({a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w});
}

// Uniform grid over the triangles of a mesh (each triangle in every cell its
// bounding box overlaps); nearest-triangle queries search shells of cells
// outward until the shell is farther than the best distance found.
class TriangleGrid {
 public:
  explicit TriangleGrid(const Mesh& m) : m_(m) {
    const int32_t nf = m.num_faces();
    for (int c = 0; c < 3; ++c) {
      lo_[c] = INFINITY;
      hi_[c] = -INFINITY;
    }
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
      const V3 p = pos(m, v);
      for (int c = 0; c < 3; ++c) {
        lo_[c] = std::min(lo_[c], p[c]);
        hi_[c] = std::max(hi_[c], p[c]);
      }
    }
    const double ext = std::max({hi_[0] - lo_[0], hi_[1] - lo_[1], hi_[2] - lo_[2], 1e-300});
    // About two triangles per cell along the surface: cells of side ~ 2 sqrt(area / nf).
    const double side = ext / std::clamp(std::cbrt(static_cast<double>(std::max(nf, 1))) * 2.0, 1.0, 256.0);
    cell_ = side;
    for (int c = 0; c < 3; ++c) dim_[c] = std::max(1, static_cast<int>((hi_[c] - lo_[c]) / side) + 1);
    const size_t ncell = static_cast<size_t>(dim_[0]) * dim_[1] * dim_[2];
    std::vector<int64_t> count(ncell + 1, 0);
    auto each_cell = [&](int32_t f, const std::function<void(size_t)>& g) {
      const auto fv = m.face(f);
      int lo[3], hi[3];
      for (int c = 0; c < 3; ++c) {
        double a = INFINITY, b = -INFINITY;
        for (int32_t v : fv) {
          const double x = c == 0 ? m.x[v] : c == 1 ? m.y[v] : m.z[v];
          a = std::min(a, x);
          b = std::max(b, x);
        }
        lo[c] = index(c, a);
        hi[c] = index(c, b);
      }
      for (int i = lo[0]; i <= hi[0]; ++i)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int k = lo[2]; k <= hi[2]; ++k) g((static_cast<size_t>(i) * dim_[1] + j) * dim_[2] + k);
    };
    for (int32_t f = 0; f < nf; ++f) each_cell(f, [&](size_t c) { ++count[c + 1]; });
    for (size_t c = 0; c < ncell; ++c) count[c + 1] += count[c];
    offsets_ = count;
    faces_.resize(static_cast<size_t>(offsets_[ncell]));
    for (int32_t f = 0; f < nf; ++f) each_cell(f, [&](size_t c) { faces_[count[c]++] = f; });
  }

  // Distance from p to the nearest triangle (fan-triangulated polygons).
  double distance(const V3& p) const {
    int ci[3];
    for (int c = 0; c < 3; ++c) ci[c] = index(c, p[c]);
    double best = INFINITY;
    const int maxr = std::max({dim_[0], dim_[1], dim_[2]});
    for (int r = 0; r <= maxr; ++r) {
      // Points outside the box: the shell bound counts from the clamped cell.
      double out = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = std::max({lo_[c] - p[c], p[c] - hi_[c], 0.0});
        out += d * d;
      }
      const double shell = std::max(0.0, (r - 1) * cell_);
      if (best < INFINITY && best <= shell * shell + out) break;
      for (int i = ci[0] - r; i <= ci[0] + r; ++i)
        for (int j = ci[1] - r; j <= ci[1] + r; ++j)
          for (int k = ci[2] - r; k <= ci[2] + r; ++k) {
            if (std::max({std::abs(i - ci[0]), std::abs(j - ci[1]), std::abs(k - ci[2])}) != r) continue;
            if (i < 0 || j < 0 || k < 0 || i >= dim_[0] || j >= dim_[1] || k >= dim_[2]) continue;
            const size_t c = (static_cast<size_t>(i) * dim_[1] + j) * dim_[2] + k;
            for (int64_t q = offsets_[c]; q < offsets_[c + 1]; ++q) {
              const auto fv = m_.face(faces_[q]);
              for (size_t t = 1; t + 1 < fv.size(); ++t)
                best = std::min(best, point_triangle_dist2(p, pos(m_, fv[0]), pos(m_, fv[t]), pos(m_, fv[t + 1])));
            }
          }
    }
    return std::sqrt(best);
  }

 private:
  int index(int c, double x) const {
    return std::clamp(static_cast<int>(std::floor((x - lo_[c]) / cell_)), 0, dim_[c] - 1);
  }
  const Mesh& m_;
  double lo_[3], hi_[3], cell_ = 1;
  int dim_[3] = {1, 1, 1};
  std::vector<int64_t> offsets_;
  std::vector<int32_t> faces_;
};

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

}  // namespace

double hausdorff_distance(const Mesh& a, const Mesh& b) {
  if (a.num_faces() == 0 || b.num_faces() == 0) fail(ErrorCode::BadUsage, "hausdorff: both meshes need faces");
  const TriangleGrid ga(a), gb(b);
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
  return std::max({ab, ba, samples_to(a, gb)});
}

RemeshStats mesh_topology_stats(const Mesh& m) {
  const MeshReport rep = analyze_mesh(m);
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

RemeshStats remesh_stats(const Mesh& input, const Mesh& remesh, bool hausdorff) {
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
    double diag2 = 0;
    const MeshReport rep = analyze_mesh(input);
    for (int c = 0; c < 3; ++c) diag2 += (rep.bbox_max[c] - rep.bbox_min[c]) * (rep.bbox_max[c] - rep.bbox_min[c]);
    s.hausdorff_rel = diag2 > 0 ? hausdorff_distance(input, remesh) / std::sqrt(diag2) : 0.0;
  }
  return s;
}

}  // namespace locus
