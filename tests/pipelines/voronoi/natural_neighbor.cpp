// Tests for pipelines/natural_neighbor (thesis §3.7.2).
// Oracles: the defining properties of barycentric coordinates (non-negative,
// partition of unity, Lagrange property) and, in the plane, linear precision
// (sum_i b_i p_i = q for natural-neighbor coordinates; discretization error only).
#include "locus/pipelines/voronoi/natural_neighbor.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"

using namespace locus;

namespace {

// The face of a planar mesh (z = 0) containing (x, y), with barycentric weights.
SurfacePoint locate(const Mesh& m, double x, double y) {
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t a = m.f0[f], b = m.f1[f], c = m.f2[f];
    const double d = (m.y[b] - m.y[c]) * (m.x[a] - m.x[c]) + (m.x[c] - m.x[b]) * (m.y[a] - m.y[c]);
    const double l0 = ((m.y[b] - m.y[c]) * (x - m.x[c]) + (m.x[c] - m.x[b]) * (y - m.y[c])) / d;
    const double l1 = ((m.y[c] - m.y[a]) * (x - m.x[c]) + (m.x[a] - m.x[c]) * (y - m.y[c])) / d;
    const double l2 = 1 - l0 - l1;
    if (l0 >= 0 && l1 >= 0 && l2 >= 0) return SurfacePoint{f, -1, {l0, l1, l2}};
  }
  FAIL("point outside the mesh");
  return {};
}

}  // namespace

TEST_CASE("natural neighbor coordinates in the plane: non-negative, sum 1, linear precision, Lagrange") {
  const Mesh m = make_grid(64, 0.2, 3);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  // Two rings of sites around the center, so the query cells stay inside the square.
  std::vector<SurfacePoint> sites;
  std::vector<std::array<double, 2>> pos;
  for (int ring = 0; ring < 2; ++ring)
    for (int k = 0; k < 7 + 5 * ring; ++k) {
      const double ang = 2 * M_PI * k / (7 + 5 * ring) + 0.3 * ring;
      const double r = ring == 0 ? 0.2 : 0.4;
      pos.push_back({0.5 + r * std::cos(ang), 0.5 + r * std::sin(ang)});
      sites.push_back(locate(m, pos.back()[0], pos.back()[1]));
    }
  const NaturalNeighborField F = prepare_natural_neighbors(H, m, sites, {});
  const double h = H.h;
  double worst = 0;
  const double queries[][2] = {{0.5, 0.5}, {0.53, 0.47}, {0.45, 0.58}, {0.6, 0.52}, {0.41, 0.43}};
  for (const auto& qq : queries) {
    const NaturalCoordinates c = natural_neighbor_coordinates(F, m, locate(m, qq[0], qq[1]));
    double sum = 0, x = 0, y = 0;
    int used = 0;
    for (size_t s = 0; s < sites.size(); ++s) {
      CHECK(c.weight[s] >= 0);
      sum += c.weight[s];
      x += c.weight[s] * pos[s][0];
      y += c.weight[s] * pos[s][1];
      used += c.weight[s] > 0;
    }
    CHECK(sum == doctest::Approx(1).epsilon(1e-12));
    CHECK(!c.at_site);
    CHECK(!c.degenerate);
    CHECK(used >= 3);
    CHECK(c.clamped < 1e-6);
    // The outer ring is not a natural neighbor of points near the center (locality).
    for (size_t s = 7; s < sites.size(); ++s) CHECK(c.weight[s] == 0);
    worst = std::max(worst, std::hypot(x - qq[0], y - qq[1]));
  }
  INFO("worst linear-precision error " << worst / h << " h");
  // Linear precision up to the discretization: well below the site spacing (0.17 = 11 h).
  CHECK(worst < 0.5 * h);
  // Lagrange property at a site and continuity next to it.
  const NaturalCoordinates at = natural_neighbor_coordinates(F, m, sites[2]);
  CHECK(at.at_site);
  CHECK(at.weight[2] == 1.0);
  const NaturalCoordinates near = natural_neighbor_coordinates(F, m, locate(m, pos[2][0] + 0.3 * h, pos[2][1]));
  CHECK(near.weight[2] > 0.6);
}

TEST_CASE("natural neighbor coordinates on a sphere: properties; bad input") {
  const Mesh m = make_icosphere(3);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const std::vector<SurfacePoint> sites = random_surface_points(m, 12, 7);
  const NaturalNeighborField F = prepare_natural_neighbors(H, m, sites, {});
  const std::vector<SurfacePoint> qs = random_surface_points(m, 10, 99);
  for (const SurfacePoint& q : qs) {
    const NaturalCoordinates c = natural_neighbor_coordinates(F, m, q);
    double sum = 0;
    for (double w : c.weight) {
      CHECK(w >= 0);
      sum += w;
    }
    CHECK(sum == doctest::Approx(1).epsilon(1e-12));
  }
  CHECK_THROWS_AS(natural_neighbor_coordinates(F, m, SurfacePoint{m.num_faces(), -1, {1, 0, 0}}), Error);
  CHECK_THROWS_AS(natural_neighbor_coordinates(F, m, qs[0], std::vector<double>(3, 0.0)), Error);
  CHECK_THROWS_AS(prepare_natural_neighbors(H, m, std::span<const SurfacePoint>{}, {}), Error);
}

TEST_CASE("natural neighbor coordinates8: 8 queries on one pass give each query's own coordinates, bit for bit") {
  // Oracle: the one-query path on the same heat, lane by lane (a vertex of the
  // batch's mask, border or share read for the wrong lane changes some weight).
  const Mesh m = make_icosphere(3);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const std::vector<SurfacePoint> sites = random_surface_points(m, 6, 5);
  const NaturalNeighborField F = prepare_natural_neighbors(H, m, sites, {});
  std::vector<SurfacePoint> qs = random_surface_points(m, 7, 31);
  qs.insert(qs.begin() + 3, sites[2]);  // a lane at a site: its indicator, the others unaffected
  const int32_t n = m.num_vertices();
  std::vector<double> heat8(static_cast<size_t>(n) * kLanes, 0.0);
  for (int l = 0; l < kLanes; ++l) {
    int32_t sv[3];
    double sw[3];
    const int c = surface_point_support(m, qs[l], sv, sw);
    for (int k = 0; k < c; ++k) heat8[static_cast<size_t>(sv[k]) * kLanes + l] += sw[k];
  }
  solve8(H.factor, heat8);
  NaturalScratch scratch;
  std::vector<NaturalCoordinates> batch(kLanes);
  natural_neighbor_coordinates8(F, m, qs, heat8, scratch, batch);
  std::vector<double> lane(n);
  for (int l = 0; l < kLanes; ++l) {
    for (int32_t v = 0; v < n; ++v) lane[v] = heat8[static_cast<size_t>(v) * kLanes + l];
    const NaturalCoordinates one = natural_neighbor_coordinates(F, m, qs[l], lane);
    CHECK(batch[l].at_site == one.at_site);
    CHECK(batch[l].cell_area == one.cell_area);
    CHECK(batch[l].fallback_faces == one.fallback_faces);
    for (size_t i = 0; i < sites.size(); ++i) CHECK(batch[l].weight[i] == one.weight[i]);
  }
  CHECK(batch[3].at_site);
  CHECK(batch[3].weight[2] == 1.0);
  CHECK_THROWS_AS(natural_neighbor_coordinates8(F, m, qs, std::vector<double>(n, 0.0), scratch, batch), Error);
}
