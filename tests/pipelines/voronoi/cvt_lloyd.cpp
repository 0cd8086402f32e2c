// Tests for pipelines/cvt_lloyd and pipelines/cvt_quality (thesis §3.7.1).
// Oracles: analytic facts (an icosahedron with one cell per vertex has an
// equilateral dual; Lloyd lowers the CVT energy, so cell areas even out and dual
// angles grow on a sphere); the full solver for the localized one; runs with 1 and 2
// threads for determinism.
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/cvt_quality.hpp"

using namespace locus;

TEST_CASE("cvt quality: icosahedron with one cell per vertex has an equilateral dual and equal areas") {
  const Mesh m = make_icosphere(0);
  std::vector<int32_t> label(m.num_vertices());
  std::vector<SurfacePoint> sites;
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    label[v] = v;
    sites.push_back(vertex_point(v));
  }
  const CvtQuality q = cvt_quality(m, label, sites);
  CHECK(q.dual_triangles == 20);
  CHECK(q.min_angle_deg == doctest::Approx(60).epsilon(1e-9));
  CHECK(q.mean_angle_deg == doctest::Approx(60).epsilon(1e-9));
  CHECK(q.area_cv < 1e-12);
  CHECK(q.area_variance < 1e-20);
  // Two cells: no corner, areas 1/12 vs 11/12 of the total.
  std::vector<int32_t> two(m.num_vertices(), 0);
  two[0] = 1;
  const CvtQuality q2 = cvt_quality(m, two, std::vector<SurfacePoint>{vertex_point(1), vertex_point(0)});
  CHECK(q2.dual_triangles == 0);
  CHECK(q2.area_variance == doctest::Approx(((11.0 / 12 - 0.5) * (11.0 / 12 - 0.5) + (1.0 / 12 - 0.5) * (1.0 / 12 - 0.5)) / 2));
  CHECK_THROWS_AS(cvt_quality(m, std::vector<int32_t>(m.num_vertices(), 2), std::span<const SurfacePoint>(sites).subspan(0, 2)), Error);
}

TEST_CASE("cvt: Lloyd on an icosphere raises the mean dual angle and evens out cell areas") {
  const Mesh m = make_icosphere(4);
  LloydOptions o;
  o.sites = 30;
  o.seed = 3;
  o.iterations = 0;
  const LloydResult r0 = cvt_lloyd(m, o, {});
  o.iterations = 12;
  const LloydResult r = cvt_lloyd(m, o, {});
  const CvtQuality q0 = cvt_quality(m, r0.label, r0.sites), q = cvt_quality(m, r.label, r.sites);
  INFO("mean angle " << q0.mean_angle_deg << " -> " << q.mean_angle_deg << ", area variance " << q0.area_variance
                     << " -> " << q.area_variance);
  CHECK(q.mean_angle_deg > q0.mean_angle_deg + 5);
  CHECK(q.mean_angle_deg > 45);
  CHECK(q.area_variance < 0.25 * q0.area_variance);
  CHECK(q.empty_cells == 0);
  CHECK(r.iter_s.size() == 12);
  // Euler: a sphere tessellated into N cells with only 3-valent corners has 2N - 4 of them.
  CHECK(q.dual_triangles == 2 * o.sites - 4);
  // The reported worst triangle: its smallest angle by the law of cosines is the minimum.
  double pts[3][3];
  for (int k = 0; k < 3; ++k) {
    REQUIRE(q.min_angle_sites[k] >= 0);
    const auto p = surface_point_position(m, r.sites[q.min_angle_sites[k]]);
    for (int c = 0; c < 3; ++c) pts[k][c] = p[c];
  }
  auto dist = [&](int a, int b) {
    return std::sqrt((pts[a][0] - pts[b][0]) * (pts[a][0] - pts[b][0]) + (pts[a][1] - pts[b][1]) * (pts[a][1] - pts[b][1]) +
                     (pts[a][2] - pts[b][2]) * (pts[a][2] - pts[b][2]));
  };
  double len[3] = {dist(1, 2), dist(0, 2), dist(0, 1)};
  std::sort(len, len + 3);  // the smallest angle is opposite the shortest side
  const double smallest = std::acos((len[1] * len[1] + len[2] * len[2] - len[0] * len[0]) / (2 * len[1] * len[2]));
  CHECK(smallest * 180 / M_PI == doctest::Approx(q.min_angle_deg).epsilon(1e-9));
  CHECK(q.min_angle_deg < q.mean_angle_deg);
}

TEST_CASE("cvt: split-triangle cell sources escape the vertex-quantized fixed point (sphere, 100 sites)") {
  // With cells as unions of vertex stars Lloyd stops moving once no label changes,
  // far from the CVT; splitting triangles along the bisectors keeps the sites moving.
  // Reference: a CVT of 100 points on the sphere has a mean smallest dual angle of
  // about 52-54 degrees and nearly equal cell areas.
  const Mesh m = make_icosphere(4);
  LloydOptions o;
  o.sites = 100;
  o.iterations = 40;
  o.split_faces = false;
  const LloydResult a = cvt_lloyd(m, o, {});
  o.split_faces = true;
  const LloydResult b = cvt_lloyd(m, o, {});
  const CvtQuality qa = cvt_quality(m, a.label, a.sites), qb = cvt_quality(m, b.label, b.sites);
  double cva = 0, cvb = 0, var = 0;
  cell_area_spread(a.cell_area, cva, var);
  cell_area_spread(b.cell_area, cvb, var);
  INFO("vertex cells: mean " << qa.mean_angle_deg << " cv " << cva << "; split: mean " << qb.mean_angle_deg << " cv " << cvb);
  CHECK(qb.mean_angle_deg > 50);
  CHECK(qb.mean_angle_deg > qa.mean_angle_deg + 2);
  CHECK(cvb < 0.6 * cva);
  CHECK(b.fallback_faces < 40 * m.num_faces() / 100);  // localized solves: missing heat values are rare
  // Lloyd does not raise the energy (up to the discretization): last <= first.
  CHECK(b.energy.back() < b.energy.front());
}

TEST_CASE("cvt: localized and full solvers give close results; bit-identical with 1 and 2 threads") {
  const Mesh m = make_icosphere(4);
  const double h = mean_edge_length(m);
  LloydOptions o;
  o.sites = 40;
  o.seed = 5;
  o.iterations = 5;
  RunContext one, two;
  one.threads = 1;
  two.threads = 2;
  const LloydResult a = cvt_lloyd(m, o, one);
  const LloydResult b = cvt_lloyd(m, o, two);
  REQUIRE(a.sites.size() == b.sites.size());
  for (size_t s = 0; s < a.sites.size(); ++s) {
    CHECK(a.sites[s].face == b.sites[s].face);
    CHECK(a.sites[s].vertex == b.sites[s].vertex);
    for (int k = 0; k < 3; ++k) CHECK(a.sites[s].bary[k] == b.sites[s].bary[k]);  // bitwise equal
  }
  CHECK(a.label == b.label);
  CHECK(a.mean_kept_fraction < 0.95);  // the localized solves did skip part of the mesh

  o.solver = LloydOptions::Solver::Full;
  const LloydResult f = cvt_lloyd(m, o, two);
  double worst = 0;
  for (size_t s = 0; s < a.sites.size(); ++s) {
    const auto p = surface_point_position(m, a.sites[s]), q = surface_point_position(m, f.sites[s]);
    worst = std::max(worst, std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                      (p[2] - q[2]) * (p[2] - q[2])));
  }
  INFO("largest site distance local vs full: " << worst / h << " h");
  CHECK(worst < 0.5 * h);
  const CvtQuality qa = cvt_quality(m, a.label, a.sites), qf = cvt_quality(m, f.label, f.sites);
  CHECK(std::abs(qa.mean_angle_deg - qf.mean_angle_deg) < 1.0);
}

TEST_CASE("cvt: anisotropic lift runs on a torus; cancellation stops with Error(Cancelled)") {
  const Mesh m = make_torus(40, 16);
  LloydOptions o;
  o.sites = 20;
  o.iterations = 3;
  o.anisotropy = 0.05;
  const LloydResult r = cvt_lloyd(m, o, {});
  const CvtQuality q = cvt_quality(m, r.label, r.sites);
  CHECK(q.empty_cells == 0);
  CHECK(r.unreached == 0);

  std::atomic<bool> stop{true};
  RunContext ctx;
  ctx.cancel = &stop;
  try {
    cvt_lloyd(m, o, ctx);
    FAIL("not cancelled");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::Cancelled);
  }
  o.sites = m.num_vertices() + 1;
  CHECK_THROWS_AS(cvt_lloyd(m, o, {}), Error);
}

namespace {

Mesh scaled_to_unit_area(Mesh m) {
  const auto mass = lumped_mass(m);
  double area = 0;
  for (double a : mass) area += a;
  const double s = 1.0 / std::sqrt(area);
  for (auto* c : {&m.x, &m.y, &m.z})
    for (double& x : *c) x *= s;
  return m;
}

// 100 Lloyd iterations with the defaults (t = kLloydTFactor h^2), seed 1, on each
// unit-area mesh: the cells cover the surface once and their area variance is at
// most `bound` (the figures are printed).
void check_area_variance(const Mesh& sphere, const Mesh& torus, int32_t sites, double bound) {
  for (const Mesh* m : {&sphere, &torus}) {
    LloydOptions o;
    o.sites = sites;
    o.iterations = 100;
    const LloydResult r = cvt_lloyd(*m, o, {});
    double cv = 0, var = 0;
    cell_area_spread(r.cell_area, cv, var);
    double total = 0;
    for (double a : r.cell_area) total += a;
    CHECK(total == doctest::Approx(1.0).epsilon(1e-9));
    MESSAGE(std::string(m == &sphere ? "sphere " : "torus ") << sites << " sites: area variance " << var << ", cv " << cv);
    CHECK(var <= bound);
  }
}

}  // namespace

// Thesis §3.7.1: on a torus and a sphere of unit area (similar resolution), 20 and 500
// sites, 100 iterations: cell-area variance ~1e-6 and ~1e-8; the targets here are
// 2e-6 and 2e-8. Both cases use `locus cvt`'s defaults (t = 4h^2, two fit rings) and
// split-triangle areas, seed 1.
// 500 sites: the bound needs ~90 vertices per cell on the torus. Measured (seed 1;
// seeds 2 and 3 in brackets, measured unscaled): icosphere 5 (10242 vertices) 1.79e-8
// (1.74e-8, 1.09e-8),
// 320 x 144 torus (46080 vertices) 1.87e-8 (1.36e-8, 1.40e-8); the 160 x 72 torus
// gives 2.6e-8, and at t = h^2 the 320 x 144 torus gives 2.5e-8. ~25 s, hence stress.
// With the weighted centroid refit (fit_sigma 1), seed 1: 1.76e-8, 1.80e-8.
TEST_CASE("cvt stress: cell-area variance on a unit-area sphere and torus, 500 sites, 100 iterations" *
          doctest::test_suite("stress")) {
  check_area_variance(scaled_to_unit_area(make_icosphere(5)), scaled_to_unit_area(make_torus(320, 144)), 500, 2e-8);
}

// 20 sites: not met, and not reachable: the exact geodesic CVT of the sphere from the
// same initial sites has variance 4.6-4.9e-6 itself (study below; its cells are
// pentagons and hexagons; Lloyd on a 200k-point quadrature from 40 random starts, 400
// iterations each, never got below 4.2e-6). Measured with the defaults above: sphere
// 3.6e-6, torus 6.1e-6 (4x finer meshes do not lower them; with fit_sigma 1: 3.50e-6,
// 6.03e-6). Hence may_fail; the figures are printed.
TEST_CASE("cvt stress: cell-area variance on a unit-area sphere and torus, 20 sites, 100 iterations" *
          doctest::test_suite("stress") * doctest::may_fail()) {
  check_area_variance(scaled_to_unit_area(make_icosphere(5)), scaled_to_unit_area(make_torus(160, 72)), 20, 2e-6);
}

namespace {

// Oracle for the sphere: the geodesic CVT of the sphere by Lloyd on a Fibonacci
// lattice of `points` equal-weight quadrature points (the geodesic Voronoi cell of a
// point is its nearest site in R^3; the centroid is the normalized mean of the cell's
// points). Sites are unit vectors (updated in place); returns the cell areas as
// fractions of the sphere.
std::vector<double> exact_sphere_lloyd(std::vector<std::array<double, 3>>& site, int iterations, int32_t points) {
  const size_t ns = site.size();
  std::vector<std::array<double, 3>> p(points);
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int32_t i = 0; i < points; ++i) {
    const double z = 1 - (2.0 * i + 1) / points, r = std::sqrt(1 - z * z);
    p[i] = {r * std::cos(golden * i), r * std::sin(golden * i), z};
  }
  std::vector<double> area(ns);
  for (int it = 0; it <= iterations; ++it) {
    std::vector<std::array<double, 3>> sum(ns, {0, 0, 0});
    std::vector<int64_t> count(ns, 0);
    for (const auto& q : p) {
      size_t best = 0;
      double bd = -2;
      for (size_t s = 0; s < ns; ++s) {
        const double d = q[0] * site[s][0] + q[1] * site[s][1] + q[2] * site[s][2];
        if (d > bd) {
          bd = d;
          best = s;
        }
      }
      for (int c = 0; c < 3; ++c) sum[best][c] += q[c];
      ++count[best];
    }
    for (size_t s = 0; s < ns; ++s) area[s] = static_cast<double>(count[s]) / points;
    if (it == iterations) break;  // areas of the cells of the final sites
    for (size_t s = 0; s < ns; ++s) {
      const double l = std::sqrt(sum[s][0] * sum[s][0] + sum[s][1] * sum[s][1] + sum[s][2] * sum[s][2]);
      if (l > 0) site[s] = {sum[s][0] / l, sum[s][1] / l, sum[s][2] / l};
    }
  }
  return area;
}

}  // namespace

// Why the 20-site target of the stress test above is not met: the exact geodesic CVT
// of the sphere with 20 sites does not have equal cells (pentagons and hexagons), and
// its own area variance is above 2e-6. Same initial sites, 100 Lloyd iterations each;
// the heat CVT's variance is checked against the exact CVT's (not against a fixed
// number), and both are printed. Takes a few seconds (quadrature), hence skipped.
TEST_CASE("cvt study: sphere, 20 sites: heat-CVT cell-area variance vs the exact geodesic CVT" *
          doctest::test_suite("stress") * doctest::skip()) {
  const Mesh m = scaled_to_unit_area(make_icosphere(5));
  LloydOptions o;
  o.sites = 20;
  o.iterations = 100;
  const std::vector<SurfacePoint> init = random_surface_points(m, o.sites, 1);
  const LloydResult r = cvt_lloyd(m, init, o, {});
  double cv = 0, var = 0;
  cell_area_spread(r.cell_area, cv, var);
  std::vector<std::array<double, 3>> site;
  for (const SurfacePoint& p : init) {
    const auto x = surface_point_position(m, p);
    const double l = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    site.push_back({x[0] / l, x[1] / l, x[2] / l});
  }
  const std::vector<double> exact = exact_sphere_lloyd(site, 100, 400000);
  double ecv = 0, evar = 0;
  cell_area_spread(exact, ecv, evar);
  MESSAGE("sphere 20 sites: heat CVT area variance " << var << " (cv " << cv << "), exact geodesic CVT " << evar
                                                     << " (cv " << ecv << ")");
  CHECK(evar > 2e-6);            // the 2e-6 bound is below the exact CVT's own spread
  CHECK(var < 1.5 * evar);       // the heat CVT is as even as the exact one
  // Same configuration: the sorted cell areas agree within a few percent of the mean area.
  std::vector<double> a = r.cell_area, b = exact;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  double worst = 0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]) / (1.0 / o.sites));
  MESSAGE("largest difference of sorted cell areas: " << worst << " of the mean area");
  CHECK(worst < 0.05);
}

// The localized first labels come from the initial sites' Dijkstra cells (their
// two rings of neighbor cells as kept sets) or from Dijkstra balls per site:
// with no iteration the labels are those first labels of the random sites, and
// both must agree with full solves wherever the heat is not nearly tied (away
// from cell boundaries), as the localized heat Voronoi does.
TEST_CASE("cvt: first labels from Dijkstra cells or balls match the full solve away from cell boundaries") {
  const Mesh m = make_icosphere(4);
  LloydOptions o;
  o.sites = 60;
  o.seed = 3;
  o.iterations = 0;
  o.solver = LloydOptions::Solver::Full;
  const LloydResult full = cvt_lloyd(m, o, {});
  o.solver = LloydOptions::Solver::Local;
  const Adjacency adj = vertex_adjacency(m);
  for (bool cells : {true, false}) {
    CAPTURE(cells);
    o.init_cells = cells;
    const LloydResult loc = cvt_lloyd(m, o, {});
    CHECK(loc.unreached == 0);
    int32_t differ = 0, differ_inside = 0;
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
      if (loc.label[v] == full.label[v]) continue;
      ++differ;
      bool boundary = false;
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p)
        boundary |= full.label[adj.neighbors[p]] != full.label[v];
      differ_inside += !boundary;
    }
    CHECK(differ_inside == 0);
    CHECK(differ <= m.num_vertices() / 100);
  }
}

TEST_CASE("cvt: graph-metric first iterations (graph_iterations): counted in iterations, deterministic, better than none") {
  const Mesh m = make_icosphere(4);
  LloydOptions o;
  o.sites = 40;
  o.seed = 5;
  o.iterations = 6;
  SUBCASE("automatic: none below kGraphLloydVertices") {
    const LloydResult r = cvt_lloyd(m, o, {});
    CHECK(r.graph_iterations == 0);
    CHECK(r.iter_s.size() == 6);
  }
  SUBCASE("four graph iterations, then two heat iterations; 1 and 2 threads bit-identical") {
    o.graph_iterations = 4;
    RunContext one, two;
    one.threads = 1;
    two.threads = 2;
    const LloydResult a = cvt_lloyd(m, o, one);
    const LloydResult b = cvt_lloyd(m, o, two);
    CHECK(a.graph_iterations == 4);
    CHECK(a.iter_s.size() == 2);
    REQUIRE(a.sites.size() == b.sites.size());
    for (size_t s = 0; s < a.sites.size(); ++s) {
      CHECK(a.sites[s].face == b.sites[s].face);
      for (int k = 0; k < 3; ++k) CHECK(a.sites[s].bary[k] == b.sites[s].bary[k]);  // bitwise equal
    }
    CHECK(a.label == b.label);
    // Against two heat iterations from the random sites: the graph start is further.
    LloydOptions h = o;
    h.graph_iterations = 0;
    h.iterations = 2;
    const LloydResult c = cvt_lloyd(m, h, one);
    INFO("energy graph start " << a.energy.back() << ", random start " << c.energy.back());
    CHECK(a.energy.back() < c.energy.back());
    CHECK(cvt_quality(m, a.label, a.sites).mean_angle_deg > cvt_quality(m, c.label, c.sites).mean_angle_deg);
  }
  SUBCASE("more graph iterations than iterations: all of them in the graph metric") {
    o.graph_iterations = 9;
    const LloydResult r = cvt_lloyd(m, o, {});
    CHECK(r.graph_iterations == 6);
    CHECK(r.iter_s.empty());
    CHECK(r.label.size() == static_cast<size_t>(m.num_vertices()));
  }
  SUBCASE("below -1: bad usage") {
    o.graph_iterations = -2;
    CHECK_THROWS_AS(cvt_lloyd(m, o, {}), Error);
  }
}
