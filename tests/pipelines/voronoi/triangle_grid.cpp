// The triangle grid's nearest-point queries (pipelines/src/voronoi/triangle_grid.cpp)
// on a mesh of long thin triangles: an open cylinder whose 512 side triangles are
// each as tall as the mesh, so they pass far more grid cells than the table's
// first size (the construction used to probe a full table forever): tilted
// so that their bounding boxes fill the grid. Oracle:
// the nearest point by brute force over every triangle.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "locus/pipelines/voronoi/triangle_grid.hpp"

using namespace locus;

TEST_CASE("triangle grid: a tall open cylinder of thin triangles builds, and its queries equal brute force") {
  Mesh m;
  const int n = 256;
  // Axis along (1, 1, 1) (as in assimp's NFF cylinder): every side triangle's
  // bounding box then spans most of the grid's box.
  const double s3 = 1 / std::sqrt(3.0), s2 = 1 / std::sqrt(2.0), s6 = 1 / std::sqrt(6.0);
  const double d[3] = {s3, s3, s3}, e1[3] = {s2, -s2, 0}, e2[3] = {s6, s6, -2 * s6};
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    for (const double h : {-15.0, 15.0}) {
      double x[3];
      for (int c = 0; c < 3; ++c) x[c] = h * d[c] + 5 * (std::cos(a) * e1[c] + std::sin(a) * e2[c]);
      m.add_vertex(x[0], x[1], x[2]);
    }
  }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = 2 * i + 1, c = 2 * ((i + 1) % n), d = c + 1;
    m.add_triangle(a, c, b), m.add_triangle(b, c, d);
  }
  const TriangleGrid grid(m);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  for (int q = 0; q < 200; ++q) {
    const std::array<double, 3> p{u(rng), u(rng), u(rng)};
    double best = INFINITY;
    for (int32_t f = 0; f < m.num_faces(); ++f) {
      const auto fv = m.face(f);
      const std::array<double, 3> x = closest_point_on_triangle(p, {m.x[fv[0]], m.y[fv[0]], m.z[fv[0]]},
                                                                {m.x[fv[1]], m.y[fv[1]], m.z[fv[1]]},
                                                                {m.x[fv[2]], m.y[fv[2]], m.z[fv[2]]});
      best = std::min(best, std::hypot(x[0] - p[0], x[1] - p[1], x[2] - p[2]));
    }
    CHECK(std::abs(grid.distance(p) - best) < 1e-9);
  }
}
