// Tests for pipelines/voronoi restricted_dual, cvt_remesh and remesh_quality (thesis §3.7.1).
// Oracles: the sphere (the dual of a Euclidean Voronoi partition of points on a
// sphere is their convex hull: every triangle's plane has all other sites on one
// side, and a closed genus-0 dual has 2S - 4 triangles); analytic defect counts of
// hand-made partitions (bands on a sphere, halves of a tube); the topology of
// the input (kernels/mesh analyze_mesh: Euler characteristic, components,
// boundary loops) for the remesh of generated and real meshes; distances
// the Hausdorff distance's tests are in remesh_quality.cpp.
#include "locus/pipelines/voronoi/cvt_remesh.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/voronoi/remesh_optimize.hpp"
#include "locus/pipelines/voronoi/remesh_quality.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"
#include "locus/pipelines/voronoi/restricted_dual.hpp"

using namespace locus;

namespace {

// Open tube: nu x nv quads (split), nv + 1 rings, two boundary loops.
Mesh make_tube(int32_t nu, int32_t nv, double height = 2.0) {
  Mesh m;
  for (int32_t j = 0; j <= nv; ++j)
    for (int32_t i = 0; i < nu; ++i) {
      const double a = 2 * M_PI * i / nu + (j % 2) * M_PI / nu;  // staggered rings: near-equilateral
      m.add_vertex(std::cos(a), std::sin(a), height * j / nv);
    }
  for (int32_t j = 0; j < nv; ++j)
    for (int32_t i = 0; i < nu; ++i) {
      const int32_t a = j * nu + i, b = j * nu + (i + 1) % nu, c = (j + 1) * nu + i, d = (j + 1) * nu + (i + 1) % nu;
      if (j % 2 == 0) {
        m.add_triangle(a, b, c);
        m.add_triangle(b, d, c);
      } else {
        m.add_triangle(a, d, c);
        m.add_triangle(a, b, d);
      }
    }
  return m;
}

// The faces not within `rings` rings of the given vertices, unreferenced vertices removed.
Mesh cut_holes(const Mesh& m, const std::vector<int32_t>& centers, int rings) {
  const Adjacency adj = vertex_adjacency(m);
  std::vector<uint8_t> gone(m.num_vertices(), 0);
  std::vector<int32_t> front = centers;
  for (int32_t c : centers) gone[c] = 1;
  for (int r = 0; r < rings; ++r) {
    std::vector<int32_t> next;
    for (int32_t v : front)
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p)
        if (!gone[adj.neighbors[p]]) {
          gone[adj.neighbors[p]] = 1;
          next.push_back(adj.neighbors[p]);
        }
    front = next;
  }
  Mesh out;
  std::vector<int32_t> id(m.num_vertices(), -1);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    if (gone[v[0]] && gone[v[1]] && gone[v[2]]) continue;
    if (gone[v[0]] + gone[v[1]] + gone[v[2]] >= 2) continue;
    int32_t w[3];
    for (int k = 0; k < 3; ++k) {
      if (id[v[k]] < 0) {
        id[v[k]] = out.num_vertices();
        out.add_vertex(m.x[v[k]], m.y[v[k]], m.z[v[k]]);
      }
      w[k] = id[v[k]];
    }
    out.add_triangle(w[0], w[1], w[2]);
  }
  return out;
}

std::array<double, 3> sub(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

// The remesh shares the input's topology; returns its stats.
RemeshStats check_same_topology(const Mesh& input, const Mesh& remesh) {
  const MeshReport in = analyze_mesh(input);
  const MeshReport out = analyze_mesh(remesh);
  CHECK(out.manifold);
  CHECK(out.non_manifold_edges == 0);
  CHECK(out.non_manifold_vertices == 0);
  CHECK(out.unreferenced_vertices == 0);
  CHECK(out.components == in.components);
  CHECK(out.boundary_loops == in.boundary_loops);
  CHECK(out.euler_characteristic == in.euler_characteristic);
  const RemeshStats s = mesh_topology_stats(remesh);
  CHECK(s.genus == mesh_topology_stats(input).genus);
  return s;
}

RemeshResult remesh(const Mesh& m, int32_t sites, int32_t iterations) {
  RemeshOptions o;
  o.lloyd.sites = sites;
  o.lloyd.iterations = iterations;
  const MeshDerived d = derive_mesh(m);
  return cvt_remesh(m, d, o, RunContext{});
}

// Cached real meshes (tools/fetch_meshes.sh); tests skip when absent.
bool have_mesh(const std::string& path) {
  if (std::filesystem::exists(path)) return true;
  MESSAGE(path << " not present (run tools/fetch_meshes.sh); skipping");
  return false;
}

}  // namespace

TEST_CASE("restricted dual: Euclidean Voronoi cells of points on a sphere dualize to their convex hull") {
  const Mesh m = make_icosphere(5);  // 10242 vertices, edge ~0.02
  const int32_t ns = 24;
  std::mt19937_64 rng(1);  // generic: seed 5 has four nearly cocircular sites, whose Voronoi edge (shorter than h) the discrete cells flip
  std::normal_distribution<double> g;
  std::vector<std::array<double, 3>> p(ns);
  std::vector<SurfacePoint> sites(ns);
  for (int32_t s = 0; s < ns; ++s) {
    const double a = g(rng), b = g(rng), c = g(rng), r = std::sqrt(a * a + b * b + c * c);
    p[s] = {a / r, b / r, c / r};
    // The site: the nearest vertex (its position is the sphere point's up to h).
    int32_t best = 0;
    double bd = INFINITY;
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
      const double d = std::pow(m.x[v] - p[s][0], 2) + std::pow(m.y[v] - p[s][1], 2) + std::pow(m.z[v] - p[s][2], 2);
      if (d < bd) {
        bd = d;
        best = v;
      }
    }
    sites[s] = vertex_point(best);
    p[s] = {m.x[best], m.y[best], m.z[best]};
  }
  std::vector<int32_t> label(m.num_vertices());
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    double bd = INFINITY;
    for (int32_t s = 0; s < ns; ++s) {
      const double d = std::pow(m.x[v] - p[s][0], 2) + std::pow(m.y[v] - p[s][1], 2) + std::pow(m.z[v] - p[s][2], 2);
      if (d < bd) {
        bd = d;
        label[v] = s;
      }
    }
  }
  const DualTopology topo = dual_topology(m);
  const RestrictedDual d = restricted_dual(m, topo, label, sites);
  REQUIRE(d.defects.total() == 0);
  CHECK(d.triangles.size() == static_cast<size_t>(2 * ns - 4));
  for (const auto& t : d.triangles) {  // a hull face: every other site on the inner side, outward orientation
    const auto e1 = sub(p[t[1]], p[t[0]]), e2 = sub(p[t[2]], p[t[0]]);
    const std::array<double, 3> n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                     e1[0] * e2[1] - e1[1] * e2[0]};
    CHECK(n[0] * p[t[0]][0] + n[1] * p[t[0]][1] + n[2] * p[t[0]][2] > 0);  // faces outward like the icosphere
    for (int32_t s = 0; s < ns; ++s) {
      if (s == t[0] || s == t[1] || s == t[2]) continue;
      const auto q = sub(p[s], p[t[0]]);
      CHECK(n[0] * q[0] + n[1] * q[1] + n[2] * q[2] < 0);
    }
  }
  // On a borrowed edge incidence (a caller's derived data): the same hull.
  const EdgeIncidence inc = edge_incidence(m);
  const RestrictedDual b = restricted_dual(m, dual_topology(m, inc), label, sites);
  CHECK(b.defects.total() == 0);
  CHECK(b.triangles == d.triangles);
  CHECK_THROWS_AS(dual_topology(m, edge_incidence(make_icosphere(1))), Error);
  std::vector<int32_t> vs;
  const Mesh dm = dual_mesh(m, d, sites, vs);
  CHECK(dm.num_vertices() == ns);
  check_same_topology(m, dm);
}

TEST_CASE("restricted dual: defects of hand-made partitions are counted and located") {
  const Mesh sphere = make_icosphere(3);
  const DualTopology ts = dual_topology(sphere);
  // Three bands by height: the middle cell is an annulus, both interfaces are loops.
  std::vector<int32_t> band(sphere.num_vertices());
  for (int32_t v = 0; v < sphere.num_vertices(); ++v) band[v] = sphere.z[v] > 0.5 ? 0 : sphere.z[v] < -0.5 ? 2 : 1;
  const std::vector<SurfacePoint> three = {vertex_point(0), vertex_point(1), vertex_point(2)};
  const RestrictedDual d = restricted_dual(sphere, ts, band, three);
  CHECK(d.defects.non_disk_cells == 1);
  CHECK(d.defects.loop_interfaces == 2);
  CHECK(d.defects.split_cells == 0);
  CHECK(d.defects.repeated_corners == 0);
  CHECK(d.defects.total() == 3);
  CHECK(!d.repair_vertices.empty());
  CHECK(d.repair_vertices.size() <= 3);
  CHECK(d.triangles.empty());
  std::vector<int32_t> vs;
  CHECK_THROWS_AS(dual_mesh(sphere, d, three, vs), Error);
  // Two cells of one label on opposite caps: a split cell.
  std::vector<int32_t> caps(sphere.num_vertices());
  for (int32_t v = 0; v < sphere.num_vertices(); ++v) caps[v] = std::abs(sphere.z[v]) > 0.5 ? 0 : 1;
  const RestrictedDual c = restricted_dual(sphere, ts, caps, std::vector<SurfacePoint>{vertex_point(0), vertex_point(1)});
  CHECK(c.defects.split_cells == 1);
  CHECK(c.defects.split_interfaces == 1);  // the two loops around the caps
  // A tube cut lengthwise into two halves: each boundary loop passes two cells, the
  // interface is two arcs from boundary to boundary.
  const Mesh tube = make_tube(24, 12);
  const DualTopology tt = dual_topology(tube);
  REQUIRE(tt.loops.size() == 2);
  std::vector<int32_t> half(tube.num_vertices());
  for (int32_t v = 0; v < tube.num_vertices(); ++v) half[v] = tube.y[v] > 1e-9 ? 0 : 1;
  const RestrictedDual h = restricted_dual(tube, tt, half, std::vector<SurfacePoint>{vertex_point(0), vertex_point(1)});
  CHECK(h.defects.short_boundary_loops == 2);
  CHECK(h.defects.split_interfaces == 1);
  CHECK(h.defects.boundary_interfaces == 2);
  CHECK(h.defects.non_disk_cells == 0);
  // Labels out of range are refused.
  std::vector<int32_t> bad(sphere.num_vertices(), 0);
  bad[7] = 3;
  CHECK_THROWS_AS(restricted_dual(sphere, ts, bad, three), Error);
}

TEST_CASE("cvt remesh: sphere, torus, tube, two components keep their topology") {
  SUBCASE("sphere") {
    const Mesh m = make_icosphere(4);
    const RemeshResult r = remesh(m, 200, 8);
    REQUIRE(r.complete);
    CHECK(r.remesh.num_faces() == 2 * r.remesh.num_vertices() - 4);
    CHECK(r.remesh.num_vertices() == 200 + r.added_sites - 0 /* no empty cells on a sphere */);
    const RemeshStats s = remesh_stats(m, r.remesh, true);
    CHECK(s.mean_min_angle_deg > 40);
    CHECK(s.hausdorff_rel < 0.05);
    check_same_topology(m, r.remesh);
  }
  SUBCASE("torus (genus 1)") {
    const Mesh m = make_torus(96, 40);
    const RemeshResult r = remesh(m, 250, 8);
    REQUIRE(r.complete);
    check_same_topology(m, r.remesh);
    CHECK(r.remesh.num_faces() == 2 * r.remesh.num_vertices());  // chi = 0
  }
  SUBCASE("tube (two boundary loops): dual vertices of boundary cells lie on the boundary") {
    const Mesh m = make_tube(48, 30);
    const RemeshResult r = remesh(m, 120, 8);
    REQUIRE(r.complete);
    check_same_topology(m, r.remesh);
    const auto loops = boundary_loops(r.remesh);
    REQUIRE(loops.size() == 2);
    for (const auto& loop : loops) {
      CHECK(loop.size() >= 3);
      for (int32_t v : loop) {
        const double z = r.remesh.z[v];
        CHECK((std::abs(z) < 1e-12 || std::abs(z - 2.0) < 1e-12));
      }
    }
  }
  SUBCASE("two components: every component gets sites") {
    Mesh m = make_icosphere(3);
    const Mesh b = make_torus(60, 24);
    const int32_t off = m.num_vertices();
    for (int32_t v = 0; v < b.num_vertices(); ++v) m.add_vertex(b.x[v] + 5, b.y[v], b.z[v]);
    for (int32_t f = 0; f < b.num_faces(); ++f) m.add_triangle(b.f0[f] + off, b.f1[f] + off, b.f2[f] + off);
    const RemeshResult r = remesh(m, 150, 5);
    REQUIRE(r.complete);
    check_same_topology(m, r.remesh);
  }
}

TEST_CASE("cvt remesh: real meshes (armadillo 1,000 sites, elephant genus 3, with holes, blade two loops)") {
  struct Case {
    std::string path;
    int32_t sites;
    std::vector<int32_t> holes;
  };
  const Case cases[] = {{LOCUS_MESH_CACHE_DIR "/armadillo.off", 1000, {}},
                        {LOCUS_MESH_CACHE_DIR "/elephant.off", 400, {}},
                        {LOCUS_MESH_CACHE_DIR "/elephant.off", 400, {100, 1500, 2500}},
                        {LOCUS_MESH_CACHE_DIR "/blade.off", 400, {}}};
  for (const Case& c : cases) {
    if (!have_mesh(c.path)) continue;
    CAPTURE(c.path);
    CAPTURE(c.holes.size());
    Mesh m = read_mesh(c.path);
    if (!c.holes.empty()) m = cut_holes(m, c.holes, 2);
    const RemeshResult r = remesh(m, c.sites, 4);
    REQUIRE(r.complete);
    // Written and read back through the project's reader.
    const std::string out = (std::filesystem::temp_directory_path() / "locus_remesh_test.off").string();
    write_mesh(out, r.remesh);
    const Mesh back = read_mesh(out);
    std::filesystem::remove(out);
    CHECK(back.num_vertices() == r.remesh.num_vertices());
    const RemeshStats s = check_same_topology(m, back);
    if (!c.holes.empty()) CHECK(s.boundary_loops == static_cast<int32_t>(c.holes.size()));
  }
}

TEST_CASE("cvt remesh: armadillo with 5,000 sites (long; --no-skip)" * doctest::skip()) {
  if (!have_mesh(LOCUS_MESH_CACHE_DIR "/armadillo.off")) return;
  const Mesh m = read_mesh(LOCUS_MESH_CACHE_DIR "/armadillo.off");
  const RemeshResult r = remesh(m, 5000, 20);
  REQUIRE(r.complete);
  check_same_topology(m, r.remesh);
  const RemeshStats s = remesh_stats(m, r.remesh, true);
  CHECK(s.hausdorff_rel <= 0.01);
}

TEST_CASE("remesh quality: angles of a known triangle") {
  Mesh t;
  t.add_vertex(0, 0, 0);
  t.add_vertex(1, 0, 0);
  t.add_vertex(0, 1, 0);
  t.add_triangle(0, 1, 2);
  const RemeshStats s = remesh_stats(t, t, true);
  CHECK(s.min_angle_deg == doctest::Approx(45));
  CHECK(s.mean_min_angle_deg == doctest::Approx(45));
  CHECK(s.pct_below_30_deg == 0);
  CHECK(s.hausdorff_rel == doctest::Approx(0).epsilon(1e-12));
  CHECK(s.boundary_loops == 1);
  CHECK(s.genus == 0);
}

TEST_CASE("cvt: the energy stopping rule stops at the first iteration that lowers the energy by less than the fraction") {
  const Mesh m = make_icosphere(4);
  LloydOptions o;
  o.sites = 60;
  o.iterations = 200;
  o.stop_energy = 2e-3;
  const LloydResult r = cvt_lloyd(m, o, {});
  const std::vector<double>& e = r.energy;
  REQUIRE(e.size() >= 2);
  CHECK(e.size() < 200);
  CHECK(r.iter_s.size() == e.size());
  CHECK(e[e.size() - 2] - e.back() < 2e-3 * e.back());
  for (size_t k = 1; k + 1 < e.size(); ++k) CHECK(e[k - 1] - e[k] >= 2e-3 * e[k]);
  // Without the rule: all iterations, the same first ones (the rule only stops).
  o.stop_energy = 0;
  o.iterations = static_cast<int32_t>(e.size()) + 3;
  const LloydResult full = cvt_lloyd(m, o, {});
  CHECK(full.energy.size() == e.size() + 3);
  for (size_t k = 0; k < e.size(); ++k) CHECK(full.energy[k] == e[k]);
  o.stop_energy = -1;
  CHECK_THROWS_AS(cvt_lloyd(m, o, {}), Error);
}

// A pair folded onto itself: (a, b, c) and (b, a, d) with c and d on the same
// side of ab, so the first faces -z and the second +z (a 177-degree fold: the
// 30-degree crease rule alone keeps it). On a +z input the flip to (c, a, d),
// (d, b, c) faces like the input and is taken; on the same square facing -z
// the flipped pair would be the fold, and nothing flips.
TEST_CASE("remesh optimization: a pair folded against the input is flipped open, and only against the input") {
  auto square = [](bool up) {
    Mesh in;
    for (const auto& p : std::vector<std::array<double, 2>>{{0, 0}, {1, 0}, {1, 1}, {0, 1}}) in.add_vertex(p[0], p[1], 0);
    if (up) in.add_triangle(0, 1, 2), in.add_triangle(0, 2, 3);
    else in.add_triangle(0, 2, 1), in.add_triangle(0, 3, 2);
    return in;
  };
  auto folded = [] {
    Mesh r;
    for (const auto& p : std::vector<std::array<double, 2>>{{0.2, 0.5}, {0.8, 0.5}, {0.5, 0.47}, {0.5, 0.2}})
      r.add_vertex(p[0], p[1], 0);
    r.add_triangle(0, 1, 2);  // a, b, c: -z
    r.add_triangle(1, 0, 3);  // b, a, d: +z
    return r;
  };
  RemeshOptimizeOptions o;
  o.rounds = 0;  // the flip pass alone: no smoothing, no angle sweeps
  o.angle_sweeps = o.sum_sweeps = o.hard_sweeps = 0;
  auto normal_z = [](const Mesh& r, int32_t f) {
    const int32_t a = r.f0[f], b = r.f1[f], c = r.f2[f];
    return (r.x[b] - r.x[a]) * (r.y[c] - r.y[a]) - (r.y[b] - r.y[a]) * (r.x[c] - r.x[a]);
  };
  {
    const Mesh input = square(true);
    const TriangleGrid grid(input);
    Mesh r = folded();
    const RemeshOptimizeStats st = optimize_remesh(input, grid, r, o);
    CHECK(st.flips == 1);
    REQUIRE(r.num_faces() == 2);
    for (int32_t f = 0; f < 2; ++f) {
      CHECK(normal_z(r, f) > 0);
      const std::set<int32_t> t = {r.f0[f], r.f1[f], r.f2[f]};
      CHECK((t.count(2) == 1 && t.count(3) == 1));  // both hold the new edge c-d
    }
    CHECK(remesh_stats(input, r, false).min_angle_deg > 30);
  }
  {
    const Mesh input = square(false);
    const TriangleGrid grid(input);
    Mesh r = folded();
    CHECK(optimize_remesh(input, grid, r, o).flips == 0);
    CHECK(r.f0[0] == 0);
    CHECK(r.f2[1] == 3);
  }
}

// The targeted angle repair alone (no smoothing rounds): a hexagon fan whose
// center sits near one side has thin triangles; the best place for the center
// is the hexagon's center (every angle 60 degrees), which the pattern search
// must approach; the boundary stays and the center stays on the input plane.
TEST_CASE("remesh optimization: the angle repair moves a free vertex of thin triangles towards the best angles") {
  const Mesh input = make_grid(10);  // the unit square, z = 0
  auto hexagon = [] {
    Mesh r;
    r.add_vertex(0.5, 0.25, 0);  // the center, pushed towards one side
    for (int k = 0; k < 6; ++k)
      r.add_vertex(0.5 + 0.4 * std::cos(k * M_PI / 3), 0.5 + 0.4 * std::sin(k * M_PI / 3), 0);
    for (int k = 0; k < 6; ++k) r.add_triangle(0, 1 + k, 1 + (k + 1) % 6);
    return r;
  };
  // Smallest angle over the triangles, from the coordinates.
  auto smallest = [](const Mesh& r) {
    double worst = 180;
    for (int32_t f = 0; f < r.num_faces(); ++f) {
      const int32_t t[3] = {r.f0[f], r.f1[f], r.f2[f]};
      for (int k = 0; k < 3; ++k) {
        const int32_t o = t[k], u = t[(k + 1) % 3], w = t[(k + 2) % 3];
        const double ax = r.x[u] - r.x[o], ay = r.y[u] - r.y[o], bx = r.x[w] - r.x[o], by = r.y[w] - r.y[o];
        const double c = (ax * bx + ay * by) / std::hypot(ax, ay) / std::hypot(bx, by);
        worst = std::min(worst, std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI);
      }
    }
    return worst;
  };
  const TriangleGrid grid(input);
  RemeshOptimizeOptions off;
  off.rounds = 0;
  off.angle_sweeps = 0;
  off.sum_sweeps = 0;
  Mesh a = hexagon();
  optimize_remesh(input, grid, a, off);
  CHECK(smallest(a) < 30);  // the Delaunay flips alone leave a thin triangle
  RemeshOptimizeOptions on = off;
  on.angle_sweeps = 3;
  on.angle_below_deg = 59;
  Mesh b = hexagon();
  const RemeshOptimizeStats st = optimize_remesh(input, grid, b, on);
  CHECK(st.angle_moves >= 1);
  CHECK(smallest(b) > 55);
  CHECK(std::hypot(b.x[0] - 0.5, b.y[0] - 0.5) < 0.03);
  CHECK(b.z[0] == 0);
  for (int32_t v = 1; v < 7; ++v) {
    CHECK(b.x[v] == a.x[v]);
    CHECK(b.y[v] == a.y[v]);
  }
}

// The sum's climbs (sum_sweeps): a hexagon fan whose center sits a little off
// has no triangle below 30 degrees, so the repair leaves it; the sum of the
// six smallest angles is largest (6 x 60 degrees, equilateral triangles) only
// at the hexagon's center, which the climbs must approach.
TEST_CASE("remesh optimization: the sum sweeps move a vertex towards the largest sum of smallest angles") {
  const Mesh input = make_grid(10);  // the unit square, z = 0
  auto hexagon = [] {
    Mesh r;
    r.add_vertex(0.5, 0.42, 0);  // the center, a fifth of the radius off
    for (int k = 0; k < 6; ++k)
      r.add_vertex(0.5 + 0.4 * std::cos(k * M_PI / 3), 0.5 + 0.4 * std::sin(k * M_PI / 3), 0);
    for (int k = 0; k < 6; ++k) r.add_triangle(0, 1 + k, 1 + (k + 1) % 6);
    return r;
  };
  auto mean_smallest = [](const Mesh& r) {  // degrees, from the side lengths (law of cosines)
    double sum = 0;
    for (int32_t f = 0; f < r.num_faces(); ++f) {
      const int32_t t[3] = {r.f0[f], r.f1[f], r.f2[f]};
      double worst = 180;
      for (int k = 0; k < 3; ++k) {
        auto len = [&](int32_t i, int32_t j) { return std::hypot(r.x[i] - r.x[j], r.y[i] - r.y[j]); };
        const double a = len(t[(k + 1) % 3], t[(k + 2) % 3]), b = len(t[k], t[(k + 1) % 3]), c = len(t[k], t[(k + 2) % 3]);
        worst = std::min(worst, std::acos(std::clamp((b * b + c * c - a * a) / (2 * b * c), -1.0, 1.0)) * 180 / M_PI);
      }
      sum += worst;
    }
    return sum / r.num_faces();
  };
  const TriangleGrid grid(input);
  RemeshOptimizeOptions repair;
  repair.rounds = 0;
  repair.sum_sweeps = 0;
  Mesh a = hexagon();
  const double before = mean_smallest(a);
  CHECK(before < 55);
  const RemeshOptimizeStats sa = optimize_remesh(input, grid, a, repair);
  CHECK(sa.angle_moves == 0);  // every angle is above 30 degrees: nothing to repair
  CHECK(a.y[0] == 0.42);
  RemeshOptimizeOptions sum = repair;
  sum.sum_sweeps = 3;
  Mesh b = hexagon();
  const RemeshOptimizeStats sb = optimize_remesh(input, grid, b, sum);
  CHECK(sb.angle_moves >= 1);
  CHECK(std::hypot(b.x[0] - 0.5, b.y[0] - 0.5) < 0.02);
  CHECK(mean_smallest(b) > 58);
  CHECK(b.z[0] == 0);
  for (int32_t v = 1; v < 7; ++v) {
    CHECK(b.x[v] == a.x[v]);
    CHECK(b.y[v] == a.y[v]);
  }
}
