// Tests for pipelines/voronoi remesh_boundary through the remesh (cvt_remesh.hpp,
// remesh_optimize.hpp; thesis §3.7.1): boundary vertices slide along the
// input's boundary curve and the boundary triangles get the interior's angles.
// Oracles computed here from the output alone: distances to the input's
// boundary segments, angles of every triangle, the Euler characteristic and
// boundary edges counted from the faces; the square's corners by coordinates.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/pipelines/voronoi/cvt_remesh.hpp"

using namespace locus;

namespace {

using P = std::array<double, 3>;
P at(const Mesh& m, int32_t v) { return {m.x[v], m.y[v], m.z[v]}; }

// Edges in exactly one face (each as its two vertices).
std::vector<std::array<int32_t, 2>> boundary_edges(const Mesh& m) {
  std::map<std::pair<int32_t, int32_t>, int> count;
  for (int32_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = m.face(f)[k], b = m.face(f)[(k + 1) % 3];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  std::vector<std::array<int32_t, 2>> out;
  for (const auto& [e, c] : count)
    if (c == 1) out.push_back({e.first, e.second});
  return out;
}

double segment_distance(const P& p, const P& a, const P& b) {
  const P d = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  double t = l2 > 0 ? ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  const P q = {a[0] + t * d[0] - p[0], a[1] + t * d[1] - p[1], a[2] + t * d[2] - p[2]};
  return std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
}

double min_angle_deg(const Mesh& m) {
  double worst = 180;
  for (int32_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const P o = at(m, m.face(f)[k]), u = at(m, m.face(f)[(k + 1) % 3]), w = at(m, m.face(f)[(k + 2) % 3]);
      const P a = {u[0] - o[0], u[1] - o[1], u[2] - o[2]}, b = {w[0] - o[0], w[1] - o[1], w[2] - o[2]};
      const double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) /
                       std::sqrt((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]));
      worst = std::min(worst, std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI);
    }
  return worst;
}

// Remesh m; every boundary vertex of the result on one of m's boundary edges,
// one boundary loop (as many boundary edges as boundary vertices, chi = 1).
Mesh remesh_with_boundary(const Mesh& m, int32_t sites) {
  RemeshOptions o;
  o.lloyd.sites = sites;
  o.lloyd.iterations = 8;
  const RemeshResult r = cvt_remesh(m, derive_mesh(m), o, RunContext{});
  REQUIRE(r.complete);
  const auto in_edges = boundary_edges(m), out_edges = boundary_edges(r.remesh);
  std::vector<int32_t> ends;
  for (const auto& e : out_edges) ends.insert(ends.end(), e.begin(), e.end());
  std::sort(ends.begin(), ends.end());
  const auto unique_end = std::unique(ends.begin(), ends.end());
  CHECK(static_cast<size_t>(unique_end - ends.begin()) == out_edges.size());
  CHECK(r.remesh.num_vertices() - static_cast<int64_t>(out_edges.size() + (r.remesh.num_faces() * 3 - out_edges.size()) / 2) +
            r.remesh.num_faces() ==
        1);
  for (auto it = ends.begin(); it != unique_end; ++it) {
    double best = INFINITY;
    for (const auto& e : in_edges) best = std::min(best, segment_distance(at(r.remesh, *it), at(m, e[0]), at(m, e[1])));
    CHECK(best < 1e-12);
  }
  return r.remesh;
}

}  // namespace

TEST_CASE("remesh boundary: a disk's boundary vertices stay on its boundary polygon, angles as inside") {
  const Mesh m = make_disk(16, 0.3, 5);
  const Mesh r = remesh_with_boundary(m, 60);
  CHECK(min_angle_deg(r) >= 25);
}

TEST_CASE("remesh boundary: a square keeps its four corners and its sides") {
  const Mesh m = make_grid(30, 0.5, 3);
  const Mesh r = remesh_with_boundary(m, 70);
  for (const P& c : {P{0, 0, 0}, P{1, 0, 0}, P{0, 1, 0}, P{1, 1, 0}}) {
    bool found = false;
    for (int32_t v = 0; v < r.num_vertices(); ++v) found = found || (at(r, v) == c);
    CHECK(found);
  }
  CHECK(min_angle_deg(r) >= 25);
}
