// Tests for the remesh's Hausdorff distance (pipelines/voronoi remesh_quality, thesis §3.7.1).
// Oracles: an analytic distance (a flat square over a ring with a square hole:
// the farthest point is the hole's center, half the hole's width from the
// ring) and a dense brute force (a barycentric grid on every face of both
// meshes, each point against every triangle of the other: brute_distance.hpp),
// which brackets the true distance.
#include "locus/pipelines/voronoi/remesh_quality.hpp"

#include <doctest/doctest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "brute_distance.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"

using namespace locus;

namespace {

using namespace locus::test;

// The largest distance over an n-step barycentric grid on every face, both
// ways, and how far any surface point can be from its face's grid (the
// longest edge / n / sqrt 3: the true distance is at most that much larger).
struct Dense {
  double h = 0, reach = 0;
};

Dense dense_hausdorff(const Mesh& a, const Mesh& b, int n) {
  Dense d;
  for (int dir = 0; dir < 2; ++dir) {
    const Mesh& s = dir ? b : a;
    const Mesh& t = dir ? a : b;
    for (int32_t f = 0; f < s.num_faces(); ++f) {
      const P3 p0 = at(s, s.f0[f]), p1 = at(s, s.f1[f]), p2 = at(s, s.f2[f]);
      const double longest = std::sqrt(std::max({dot(sub(p0, p1), sub(p0, p1)), dot(sub(p1, p2), sub(p1, p2)),
                                                 dot(sub(p2, p0), sub(p2, p0))}));
      d.reach = std::max(d.reach, longest / n / std::sqrt(3.0));
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          const double u = double(i) / n, v = double(j) / n, w = 1 - u - v;
          const P3 x = {w * p0[0] + u * p1[0] + v * p2[0], w * p0[1] + u * p1[1] + v * p2[1],
                        w * p0[2] + u * p1[2] + v * p2[2]};
          d.h = std::max(d.h, distance_to(t, x));
        }
    }
  }
  return d;
}

Mesh square(double side) {
  Mesh m;
  m.add_vertex(0, 0, 0);
  m.add_vertex(side, 0, 0);
  m.add_vertex(side, side, 0);
  m.add_vertex(0, side, 0);
  m.add_triangle(0, 1, 2);
  m.add_triangle(0, 2, 3);
  return m;
}

// The square [0, 4]^2 less the hole [2.5, 3.5] x [0.4, 1.4]: four quads between
// the outer and the inner square, each split in two.
Mesh ring_with_hole() {
  Mesh m;
  for (auto [x, y] : {std::pair{0.0, 0.0}, {4.0, 0.0}, {4.0, 4.0}, {0.0, 4.0}}) m.add_vertex(x, y, 0);
  for (auto [x, y] : {std::pair{2.5, 0.4}, {3.5, 0.4}, {3.5, 1.4}, {2.5, 1.4}}) m.add_vertex(x, y, 0);
  for (int32_t k = 0; k < 4; ++k) {
    const int32_t o0 = k, o1 = (k + 1) % 4, i0 = 4 + k, i1 = 4 + (k + 1) % 4;
    m.add_triangle(o0, o1, i1);
    m.add_triangle(o0, i1, i0);
  }
  return m;
}

}  // namespace

TEST_CASE("remesh quality: the Hausdorff distance finds a hole's center inside one large triangle") {
  // The farthest point of the square from the ring is the hole's center, 0.5
  // from its edges. Samples at the vertices and seven fixed points per face
  // (the edge midpoints, the centroid, three points towards the corners) give
  // 0.17 here: the nearest of them to the center, (10/3, 2/3), is 0.17 from the hole's edge.
  const Mesh ring = ring_with_hole(), sq = square(4);
  const double h = hausdorff_distance(ring, sq);
  CHECK(h <= 0.5 + 1e-12);
  CHECK(h >= 0.5 / 1.01);
  CHECK(hausdorff_distance(sq, ring) == doctest::Approx(h).epsilon(0.01));
  const Dense d = dense_hausdorff(ring, sq, 40);
  CHECK(d.h <= h * 1.01 + 1e-12);
}

TEST_CASE("remesh quality: the Hausdorff distance within 1% of a dense brute force, on any thread count") {
  const Mesh a = make_icosphere(2);
  Mesh b = make_random_sphere(60, 3);
  for (int32_t v = 0; v < b.num_vertices(); ++v) b.x[v] = 1.3 * b.x[v] + 0.1;  // an offset ellipsoid
  const double h = hausdorff_distance(a, b);
  const Dense d = dense_hausdorff(a, b, 10);
  // The true distance is at least the dense one and at most the dense one plus
  // its grid's reach; the search gives a distance it met, within 1% of the true.
  CHECK(d.h <= h * 1.01 + 1e-12);
  CHECK(h <= d.h + d.reach + 1e-12);
  CHECK(h > 0.1);
  double one = 0;
  {
    const tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = hausdorff_distance(a, b);
  }
  CHECK(one == h);  // bit for bit
}

TEST_CASE("remesh quality: a mesh is at distance zero from itself") {
  const Mesh a = make_icosphere(1);
  CHECK(hausdorff_distance(a, a) < 1e-9);
  const Mesh t = square(1);
  CHECK(hausdorff_distance(t, t) == 0);
}
