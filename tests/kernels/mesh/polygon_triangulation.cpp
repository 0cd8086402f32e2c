// Ear clipping (kernels/mesh/polygon_triangulation.hpp) against what a
// triangulation of a simple polygon must be, computed independently in the
// polygon's own 2D coordinates: k - 2 triangles over its corners, each
// counter-clockwise, each inside the polygon (centroid by ray casting), their
// areas summing to the shoelace area, every boundary edge used once — for
// convex, non-convex (L, star, comb) and random star-shaped polygons placed in
// tilted planes; refusals for collinear, coincident and self-crossing corners.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/polygon_triangulation.hpp"

namespace {

using P2 = std::array<double, 2>;
using P3 = std::array<double, 3>;

double shoelace(const std::vector<P2>& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) a += p[i][0] * p[(i + 1) % p.size()][1] - p[(i + 1) % p.size()][0] * p[i][1];
  return 0.5 * a;
}

bool inside(const std::vector<P2>& poly, const P2& q) {  // ray casting
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    if ((poly[i][1] > q[1]) != (poly[j][1] > q[1]) &&
        q[0] < (poly[j][0] - poly[i][0]) * (q[1] - poly[i][1]) / (poly[j][1] - poly[i][1]) + poly[i][0])
      in = !in;
  return in;
}

// The polygon placed in 3D on a tilted plane through `origin`.
std::vector<P3> lift(const std::vector<P2>& p, const P3& origin) {
  const P3 u{0.6, 0.0, 0.8}, v{0.48, 0.6, -0.36};  // orthonormal, u x v = (-0.48, 0.8, 0.36)
  std::vector<P3> out;
  for (const P2& q : p)
    out.push_back({origin[0] + q[0] * u[0] + q[1] * v[0], origin[1] + q[0] * u[1] + q[1] * v[1],
                   origin[2] + q[0] * u[2] + q[1] * v[2]});
  return out;
}

void check_triangulation(const std::vector<P2>& poly, const P3& origin = {0, 0, 0}) {
  CAPTURE(poly.size());
  const std::vector<P3> c = lift(poly, origin);
  const auto tris = locus::triangulate_polygon(c, "test polygon");
  REQUIRE(tris.size() == poly.size() - 2);
  const double area = shoelace(poly);
  REQUIRE(area > 0);
  double sum = 0;
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : tris) {
    for (int32_t i : t) REQUIRE((i >= 0 && i < static_cast<int32_t>(poly.size())));
    const P2 &a = poly[t[0]], &b = poly[t[1]], &d = poly[t[2]];
    const double ta = 0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]));
    CHECK(ta > 0);  // oriented like the polygon
    sum += ta;
    CHECK(inside(poly, {(a[0] + b[0] + d[0]) / 3, (a[1] + b[1] + d[1]) / 3}));
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  CHECK(sum == doctest::Approx(area).epsilon(1e-12));
  const int k = static_cast<int>(poly.size());
  for (int i = 0; i < k; ++i) CHECK(directed[{i, (i + 1) % k}] == 1);  // each boundary edge once, in order
}

}  // namespace

TEST_CASE("triangulate_polygon: convex and non-convex polygons in tilted planes") {
  check_triangulation({{0, 0}, {1, 0}, {1, 1}, {0, 1}});                                        // square
  check_triangulation({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, {1e6, -3e5, 7});        // L, far from the origin
  std::vector<P2> star;
  for (int i = 0; i < 10; ++i) {
    const double r = i % 2 ? 0.4 : 1.0, a = 2 * M_PI * i / 10;
    star.push_back({r * std::cos(a), r * std::sin(a)});
  }
  check_triangulation(star);
  // A comb: teeth deeper than wide, every slot a reflex pair.
  std::vector<P2> comb{{0, 0}, {7, 0}, {7, 3}};
  for (int t = 3; t >= 0; --t) {
    comb.push_back({2.0 * t + 0.5, 3});
    comb.push_back({2.0 * t + 0.5, 1});
    comb.push_back({2.0 * t, 1});
    comb.push_back({2.0 * t, 3});
  }
  comb.pop_back();
  comb.pop_back();
  comb.back() = {0, 3};
  check_triangulation(comb);
  // A corner on a straight edge (a T-junction vertex): not an ear itself, still triangulated.
  check_triangulation({{0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}});
  // Random star-shaped polygons (simple by construction: increasing angles, positive radii).
  uint64_t s = 12345;
  auto next = [&]() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(s >> 11) * 0x1.0p-53;
  };
  for (int trial = 0; trial < 200; ++trial) {
    const int k = 4 + static_cast<int>(next() * 40);
    // Angles with gaps below pi (jittered equal steps), so the polygon is star-shaped about the origin.
    std::vector<P2> poly;
    for (int i = 0; i < k; ++i) {
      const double a = 2 * M_PI * (i + 0.8 * next()) / k, r = 0.2 + next();
      poly.push_back({r * std::cos(a), r * std::sin(a)});
    }
    if (poly.size() >= 4) check_triangulation(poly);
  }
}

TEST_CASE("triangulate_polygon: a quad takes the diagonal that makes the better triangles") {
  // Rhombus with its short diagonal between corners 1 and 3: both triangles use it.
  const std::vector<P3> c = lift({{-2, 0}, {0, -1}, {2, 0}, {0, 1}}, {0, 0, 0});
  const auto tris = locus::triangulate_polygon(c, "rhombus");
  REQUIRE(tris.size() == 2u);
  for (const auto& t : tris) {
    int has = 0;
    for (int32_t v : t) has += v == 1 || v == 3;
    CHECK(has == 2);
  }
  // A warped (non-planar) quad still gives two triangles over its corners.
  const std::vector<P3> warped{{0, 0, 0}, {1, 0, 0.2}, {1, 1, 0}, {0, 1, 0.2}};
  CHECK(locus::triangulate_polygon(warped, "warped").size() == 2u);
}

TEST_CASE("triangulate_polygon: degenerate and self-intersecting polygons are refused, naming the face") {
  auto message = [](const std::vector<P3>& c) {
    try {
      locus::triangulate_polygon(c, "face 7 of x.obj");
    } catch (const locus::Error& e) {
      CHECK(e.code() == locus::ErrorCode::BadInput);
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string collinear = message({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  CHECK(collinear.find("face 7 of x.obj") != std::string::npos);
  CHECK(collinear.find("no area") != std::string::npos);
  const std::string bowtie = message({{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0.5, 0}});
  CHECK(bowtie.find("face 7 of x.obj") != std::string::npos);
  CHECK(bowtie.find("cross") != std::string::npos);
  // A symmetric bow-tie: its lobes cancel (no net area), still reported as crossing.
  const std::string symmetric = message({{1, 0, 0}, {2, 1, 0}, {2, 0, 0}, {1, 1, 0}});
  CHECK(symmetric.find("cross") != std::string::npos);
  const std::string same = message({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}});
  CHECK(same.find("one point") != std::string::npos);
}

TEST_CASE("triangulate_polygons: a quad cube becomes 12 triangles on the same vertices, face_of maps back") {
  locus::Mesh m;
  for (int i = 0; i < 8; ++i) m.add_vertex(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) m.add_face(locus::ConstView<int32_t>(f, 4));
  m.add_triangle(0, 1, 2);  // a triangle among the quads stays as it is
  const locus::TriangulatedMesh t = locus::triangulate_polygons(m, "cube");
  REQUIRE(t.mesh.num_faces() == 13);
  CHECK(t.mesh.is_triangle_mesh());
  CHECK(t.mesh.num_vertices() == 8);
  REQUIRE(t.face_of.size() == 13u);
  for (int32_t f = 0; f < 12; ++f) CHECK(t.face_of[f] == f / 2);
  CHECK(t.face_of[12] == 6);
  // Each quad's two triangles use exactly its corners, and the cube's area is 6.
  double area = 0;
  for (int32_t f = 0; f < 12; ++f) {
    const auto tv = t.mesh.face(f);
    for (int32_t v : tv) CHECK(std::find(q[f / 2], q[f / 2] + 4, v) != q[f / 2] + 4);
    const double e1[3] = {t.mesh.x[tv[1]] - t.mesh.x[tv[0]], t.mesh.y[tv[1]] - t.mesh.y[tv[0]], t.mesh.z[tv[1]] - t.mesh.z[tv[0]]};
    const double e2[3] = {t.mesh.x[tv[2]] - t.mesh.x[tv[0]], t.mesh.y[tv[2]] - t.mesh.y[tv[0]], t.mesh.z[tv[2]] - t.mesh.z[tv[0]]};
    const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    area += 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  }
  CHECK(area == doctest::Approx(6.0));
}
