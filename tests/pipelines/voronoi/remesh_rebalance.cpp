// Tests for the vertices moved from flat, wide regions to thin ones
// (pipelines/include/locus/pipelines/voronoi/remesh_rebalance.hpp; thesis
// §3.7.1). A flat T: a square with a strip one remesh triangle wide. Oracles:
// the triangles' angles by the law of cosines (computed here), the topology
// of kernels/mesh analyze_mesh, the vertex count, every vertex on the T's
// plane and inside it.
#include "locus/pipelines/voronoi/remesh_rebalance.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

using namespace locus;

namespace {

// The cells of the grid xs x ys inside the T (the square [0,1]^2 and the strip
// [1,3] x [0.45,0.55]), two triangles each; only the vertices they use.
Mesh t_shape(const std::vector<double>& xs, const std::vector<double>& ys) {
  auto inside = [](double x, double y) { return (x < 1 && y < 1) || (x > 1 && x < 3 && y > 0.45 && y < 0.55); };
  const size_t nx = xs.size(), ny = ys.size();
  std::vector<int32_t> id(nx * ny, -1);
  Mesh m;
  auto vid = [&](size_t i, size_t j) {
    int32_t& v = id[j * nx + i];
    if (v < 0) {
      v = m.num_vertices();
      m.add_vertex(xs[i], ys[j], 0);
    }
    return v;
  };
  for (size_t j = 0; j + 1 < ny; ++j)
    for (size_t i = 0; i + 1 < nx; ++i) {
      if (!inside(0.5 * (xs[i] + xs[i + 1]), 0.5 * (ys[j] + ys[j + 1]))) continue;
      const int32_t a = vid(i, j), b = vid(i + 1, j), c = vid(i + 1, j + 1), d = vid(i, j + 1);
      m.add_triangle(a, b, c);
      m.add_triangle(a, c, d);
    }
  return m;
}

std::vector<double> steps(double from, double to, double h) {
  std::vector<double> v;
  for (int k = 0; from + k * h <= to + 1e-9; ++k) v.push_back(from + k * h);
  return v;
}

// Law of cosines: a triangle's smallest angle in degrees.
double smallest_angle(const Mesh& m, int32_t f) {
  const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
  double l[3];
  for (int k = 0; k < 3; ++k)
    l[k] = std::hypot(m.x[v[(k + 1) % 3]] - m.x[v[(k + 2) % 3]], m.y[v[(k + 1) % 3]] - m.y[v[(k + 2) % 3]],
                      m.z[v[(k + 1) % 3]] - m.z[v[(k + 2) % 3]]);
  double best = 180;
  for (int k = 0; k < 3; ++k) {
    const double c = (l[(k + 1) % 3] * l[(k + 1) % 3] + l[(k + 2) % 3] * l[(k + 2) % 3] - l[k] * l[k]) /
                     (2 * l[(k + 1) % 3] * l[(k + 2) % 3]);
    best = std::min(best, std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI);
  }
  return best;
}

int below(const Mesh& m, double deg) {
  int n = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) n += smallest_angle(m, f) < deg;
  return n;
}

}  // namespace

TEST_CASE("remesh rebalance: a strip one triangle wide gets vertices from the flat square; count and topology kept") {
  const Mesh input = t_shape(steps(0, 3, 0.05), steps(0, 1, 0.05));
  const TriangleGrid grid(input);
  // The remesh: the square at spacing 0.1 (rows at 0.45 and 0.55 for the
  // strip's sides), the strip's two sides at spacing 0.5: its triangles
  // are 0.5 by 0.1 (11 degrees), and no vertex inside it can open them.
  std::vector<double> xs = steps(0, 1, 0.1);
  for (double x : {1.5, 2.0, 2.5, 3.0}) xs.push_back(x);
  std::vector<double> ys = {0, 0.1, 0.2, 0.3, 0.45, 0.55, 0.7, 0.8, 0.9, 1.0};
  Mesh remesh = t_shape(xs, ys);
  const Mesh before = remesh;
  REQUIRE(below(before, 25) >= 8);  // the strip's 8 triangles at least
  std::vector<int32_t> site(static_cast<size_t>(remesh.num_vertices()));
  for (size_t v = 0; v < site.size(); ++v) site[v] = static_cast<int32_t>(v);
  const RebalanceStats st = rebalance_remesh(input, grid, remesh, {}, site);
  CHECK(st.rounds > 0);
  CHECK(st.splits == st.collapses);
  CHECK(remesh.num_vertices() == before.num_vertices());
  CHECK(site.size() == static_cast<size_t>(remesh.num_vertices()));
  const MeshReport a = analyze_mesh(before), b = analyze_mesh(remesh);
  CHECK(b.manifold);
  CHECK(b.euler_characteristic == a.euler_characteristic);
  CHECK(b.boundary_loops == a.boundary_loops);
  CHECK(below(remesh, 25) < below(before, 25));
  // The strip holds more vertices than its 8 (x > 1.05: off the square).
  int strip_before = 0, strip_after = 0;
  for (int32_t v = 0; v < before.num_vertices(); ++v) strip_before += before.x[v] > 1.05;
  for (int32_t v = 0; v < remesh.num_vertices(); ++v) {
    strip_after += remesh.x[v] > 1.05;
    CHECK(std::abs(remesh.z[v]) < 1e-12);
    const bool in_t = (remesh.x[v] <= 1 + 1e-9 && remesh.y[v] >= -1e-9 && remesh.y[v] <= 1 + 1e-9) ||
                      (remesh.x[v] <= 3 + 1e-9 && remesh.y[v] >= 0.45 - 1e-9 && remesh.y[v] <= 0.55 + 1e-9);
    CHECK(in_t);
  }
  CHECK(strip_after > strip_before);
}

TEST_CASE("remesh rebalance: a remesh at both angle targets is not touched") {
  const Mesh input = make_icosphere(3);
  const TriangleGrid grid(input);
  Mesh remesh = make_icosphere(2);  // near-equilateral triangles
  double sum = 0;
  for (int32_t f = 0; f < remesh.num_faces(); ++f) sum += smallest_angle(remesh, f);
  REQUIRE(below(remesh, 25) == 0);
  REQUIRE(sum / remesh.num_faces() >= 50);
  const Mesh before = remesh;
  std::vector<int32_t> site;
  const RebalanceStats st = rebalance_remesh(input, grid, remesh, {}, site);
  CHECK(st.rounds == 0);
  CHECK(st.splits == 0);
  REQUIRE(remesh.num_vertices() == before.num_vertices());
  for (int32_t v = 0; v < remesh.num_vertices(); ++v) CHECK(remesh.x[v] == before.x[v]);
}
