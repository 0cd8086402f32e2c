// Tests for pipelines/heat_voronoi (thesis §3.4, eqs. 3.15-3.22).
// Oracles: the exact geodesic Voronoi diagram of the unit sphere (nearest
// generator by great-circle angle; bisectors lie in planes through the origin,
// so eq. 3.22 measures a point's distance to its true bisector); a dense Eigen
// solve of the heat operator (independent of locus's factor) for the top-K heat
// values; the full solve for the localized mode's labels.
#include "locus/pipelines/voronoi/heat_voronoi.hpp"

#include <Eigen/Dense>
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <vector>

#include "locus/kernels/heat/heat_batch.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/solve/solve_selective.hpp"
#include "locus/error.hpp"

using namespace locus;

namespace {

// The face of a convex sphere mesh that the ray from the origin along d crosses, as a surface point.
SurfacePoint ray_point(const Mesh& m, std::array<double, 3> d) {
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    Eigen::Matrix3d P;
    for (int k = 0; k < 3; ++k) P.col(k) = Eigen::Vector3d(m.x[v[k]], m.y[v[k]], m.z[v[k]]);
    // d * s = P * w with sum(w) = 1  <=>  P^{-1} d gives w / s up to scale.
    const Eigen::Vector3d w = P.fullPivLu().solve(Eigen::Vector3d(d[0], d[1], d[2]));
    if (w.minCoeff() >= 0 && w.sum() > 0) {
      const Eigen::Vector3d b = w / w.sum();
      return SurfacePoint{f, -1, {b[0], b[1], b[2]}};
    }
  }
  FAIL("no face crossed");
  return {};
}

const std::array<std::array<double, 3>, 3> kGen = {{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}}};

double angle_to(const Mesh& m, int32_t v, const std::array<double, 3>& g) {
  const double r = std::sqrt(m.x[v] * m.x[v] + m.y[v] * m.y[v] + m.z[v] * m.z[v]);
  return std::acos(std::clamp((m.x[v] * g[0] + m.y[v] * g[1] + m.z[v] * g[2]) / r, -1.0, 1.0));
}

// RMS of eq. 3.22 over the diagram's edge points.
double bisector_rms(const Mesh& m, double t, int32_t* n_points = nullptr) {
  std::vector<SurfacePoint> sites;
  for (const auto& g : kGen) sites.push_back(ray_point(m, g));
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, t, {});
  const HeatVoronoi V = heat_voronoi(H, m, sites, {}, {}, {});
  const VoronoiDiagram D = extract_voronoi_diagram(H, m, sites, V, {});
  double sum = 0;
  int32_t cnt = 0;
  for (size_t p = 0; p < D.points.size() / 3; ++p) {
    const int32_t a = D.point_edge_sites[2 * p], b = D.point_edge_sites[2 * p + 1];
    if (a < 0) continue;
    double nrm[3], len = 0;
    for (int c = 0; c < 3; ++c) {
      nrm[c] = kGen[a][c] - kGen[b][c];
      len += nrm[c] * nrm[c];
    }
    len = std::sqrt(len);
    const double e = (D.points[3 * p] * nrm[0] + D.points[3 * p + 1] * nrm[1] + D.points[3 * p + 2] * nrm[2]) / len;
    sum += e * e;
    ++cnt;
  }
  if (n_points) *n_points = cnt;
  return std::sqrt(sum / cnt);
}

}  // namespace

TEST_CASE("heat voronoi: sphere labels match the exact geodesic Voronoi away from bisectors") {
  const Mesh m = make_random_sphere(3000, 11);
  const double h = mean_edge_length(m);
  std::vector<SurfacePoint> sites;
  for (const auto& g : kGen) sites.push_back(ray_point(m, g));
  for (double t : {h * h, 1.0 / 128}) {
    const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, t, {});
    const HeatVoronoi V = heat_voronoi(H, m, sites, {}, {}, {});
    int32_t wrong_far = 0, wrong_near = 0;
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
      double ang[3];
      for (int g = 0; g < 3; ++g) ang[g] = angle_to(m, v, kGen[g]);
      const int best = static_cast<int>(std::min_element(ang, ang + 3) - ang);
      double second = 10;
      for (int g = 0; g < 3; ++g)
        if (g != best) second = std::min(second, ang[g]);
      if (V.label[v] != best) (second - ang[best] > 2 * h ? wrong_far : wrong_near)++;
    }
    CHECK(wrong_far == 0);
    CHECK(wrong_near < m.num_vertices() / 50);
    CHECK(V.unreached == 0);
  }
}

TEST_CASE("heat voronoi: top-K heat values equal a dense solve of (M - tL_C) u = b(p)") {
  const Mesh m = make_icosphere(2);
  const int32_t n = m.num_vertices();
  const double t = 0.05;
  std::vector<SurfacePoint> sites = random_surface_points(m, 11, 5);  // two batches, one partial
  sites[3] = vertex_point(17);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, t, {});
  const HeatVoronoi V = heat_voronoi(H, m, sites, {}, {}, {});
  const CscMatrix A = heat_operator(m, t);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) D(A.rowind[p], j) = D(j, A.rowind[p]) = A.values[p];
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(sites.size()));
  for (size_t s = 0; s < sites.size(); ++s) {
    const SurfacePoint& p = sites[s];
    if (p.face < 0) {
      B(p.vertex, s) = 1;
    } else {
      B(m.f0[p.face], s) += p.bary[0];
      B(m.f1[p.face], s) += p.bary[1];
      B(m.f2[p.face], s) += p.bary[2];
    }
  }
  const Eigen::MatrixXd U = D.ldlt().solve(B);
  for (int32_t v = 0; v < n; ++v) {
    std::vector<std::pair<double, int>> row;
    for (int s = 0; s < static_cast<int>(sites.size()); ++s) row.push_back({-U(v, s), s});
    std::sort(row.begin(), row.end());
    CHECK(V.label[v] == row[0].second);
    for (int k = 0; k < kVoronoiTopK; ++k) {
      CHECK(V.top_site[v * kVoronoiTopK + k] == row[k].second);
      CHECK(V.top_value[v * kVoronoiTopK + k] == doctest::Approx(-row[k].first).epsilon(1e-9));
    }
  }
}

TEST_CASE("heat voronoi: bisector RMS error converges quadratically in the edge length (4 resolutions)") {
  // Thesis Fig. 3.1: least-squares slope of log RMS (eq. 3.22) on log h over four
  // random spheres (h halves from one to the next); the bound is 1.7.
  // `locus-bench voronoi-convergence random-sphere` runs the same study.
  const int32_t sizes[4] = {1000, 4000, 16000, 64000};
  std::vector<Mesh> meshes;
  for (int32_t n : sizes) meshes.push_back(make_random_sphere(n, 1));
  for (double t : {1.0, 1.0 / 128}) {
    double lh[4], le[4], mx = 0, my = 0;
    for (int k = 0; k < 4; ++k) {
      lh[k] = std::log(mean_edge_length(meshes[k]));
      le[k] = std::log(bisector_rms(meshes[k], t));
      mx += lh[k] / 4;
      my += le[k] / 4;
    }
    double sxy = 0, sxx = 0;
    for (int k = 0; k < 4; ++k) {
      sxy += (lh[k] - mx) * (le[k] - my);
      sxx += (lh[k] - mx) * (lh[k] - mx);
    }
    const double slope = sxy / sxx;
    INFO("t = " << t << " rms " << std::exp(le[0]) << " -> " << std::exp(le[3]) << " slope " << slope);
    CHECK(slope >= 1.7);
    for (int k = 1; k < 4; ++k) CHECK(le[k] < le[k - 1]);
  }
}

TEST_CASE("heat voronoi: diagram structure on the sphere (three cells, two corners)") {
  const Mesh m = make_random_sphere(2000, 7);
  std::vector<SurfacePoint> sites;
  for (const auto& g : kGen) sites.push_back(ray_point(m, g));
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0, {});
  const HeatVoronoi V = heat_voronoi(H, m, sites, {}, {}, {});
  const VoronoiDiagram D = extract_voronoi_diagram(H, m, sites, V, {});
  // Three great half-circles meet at (0,0,1) and (0,0,-1): exactly two Voronoi corners
  // in exact arithmetic; the discrete labels may add a pair of close corners at a
  // triangle with three labels next to another, so allow a few.
  CHECK(D.corners >= 2);
  CHECK(D.corners <= 6);
  CHECK(D.resolved_missing == 0);  // three generators: every value is in the top-4 lists
  // Every corner point lies near a pole.
  for (size_t p = 0; p < D.points.size() / 3; ++p)
    if (D.point_edge_sites[2 * p] < 0) CHECK(std::abs(D.points[3 * p + 2]) > 0.95);
  // The polylines use every segment once.
  size_t seg = 0;
  for (const auto& l : D.polylines) seg += l.size() - 1;
  CHECK(seg == D.segments.size() / 2);
}

TEST_CASE("heat voronoi: localized (Algorithm 2) labels match the full solve with generous neighborhoods") {
  const Mesh m = make_icosphere(4);
  const int32_t n = m.num_vertices();
  const std::vector<SurfacePoint> sites = random_surface_points(m, 20, 9);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0, {});
  const HeatVoronoi full = heat_voronoi(H, m, sites, {}, {}, {});
  // Neighborhood: the vertices within 0.9 (chord) of the generator; cells of 20
  // sites on the unit sphere have radius ~0.45.
  std::vector<std::vector<int32_t>> nb(sites.size());
  for (size_t s = 0; s < sites.size(); ++s) {
    const auto p = surface_point_position(m, sites[s]);
    for (int32_t v = 0; v < n; ++v) {
      const double dx = m.x[v] - p[0], dy = m.y[v] - p[1], dz = m.z[v] - p[2];
      if (dx * dx + dy * dy + dz * dz < 0.81) nb[s].push_back(v);
    }
  }
  const HeatVoronoi loc = heat_voronoi(H, m, sites, nb, {}, {});
  // Zeroing the heat outside the kept sets (Algorithm 2) perturbs values, so labels
  // may flip only where two heats nearly tie: at vertices on a cell boundary.
  const Adjacency adj = vertex_adjacency(m);
  int32_t differ = 0, differ_inside = 0;
  for (int32_t v = 0; v < n; ++v) {
    if (loc.label[v] == full.label[v]) continue;
    ++differ;
    bool boundary = false;
    for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) boundary |= full.label[adj.neighbors[p]] != full.label[v];
    differ_inside += !boundary;
  }
  CHECK(differ_inside == 0);
  CHECK(differ <= n / 100);
  CHECK(loc.solved_entries < static_cast<int64_t>(full.batches) * n);
}

TEST_CASE("heat voronoi: bad generators are usage errors naming the generator") {
  const Mesh m = make_icosphere(1);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0, {});
  std::vector<SurfacePoint> sites = {vertex_point(0), vertex_point(m.num_vertices())};
  CHECK_THROWS_WITH_AS(heat_voronoi(H, m, sites, {}, {}, {}), doctest::Contains("generator 1"), Error);
  sites[1] = SurfacePoint{2, -1, {0.5, 0.6, 0.1}};
  CHECK_THROWS_WITH_AS(heat_voronoi(H, m, sites, {}, {}, {}), doctest::Contains("sum to 1"), Error);
  CHECK_THROWS_AS(heat_voronoi(H, m, std::vector<SurfacePoint>{}, {}, {}, {}), Error);
}

TEST_CASE("heat batch (kernels/heat): repeated kept ids removed, localized count and ids, plan() reads") {
  const Mesh m = make_icosphere(3);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const int32_t v[1] = {0};
  const double w[1] = {1.0};
  HeatBatch full;
  full.add_source(v, w);
  solve_heat_batch(H, full);
  CHECK(full.count() == H.n);
  CHECK(full.id(7) == 7);
  HeatBatch local;
  local.add_source(v, w);
  local.kept = {5, 0, 2, 5, 0, 9};
  dedupe_kept(local, H.n);
  CHECK(local.kept == std::vector<int32_t>{5, 0, 2, 9});  // first occurrences, in order
  solve_heat_batch(H, local);
  REQUIRE(local.count() == 4);
  CHECK(local.id(1) == 0);
  CHECK(local.values.size() == 4 * static_cast<size_t>(kLanes));
  std::vector<uint8_t> mark;
  const int64_t reads = selective_solve_reads(*H.factor.symbolic, local.plan(), mark);
  CHECK(reads > 0);
  CHECK(reads <= 2 * factor_entries(*H.factor.symbolic));
  local.kept = {H.n};
  CHECK_THROWS_AS(dedupe_kept(local, H.n), Error);
}

// Adding generators to a diagram (CVT remeshing's repair rounds): with whole-mesh
// neighborhoods the grown diagram's labels and top-K lists are those of a dense
// solve for all generators; with small neighborhoods only their vertices change.
TEST_CASE("heat voronoi: adding generators solves only them and matches a dense solve of all") {
  const Mesh m = make_icosphere(2);
  const int32_t n = m.num_vertices();
  const double t = 0.05;
  std::vector<SurfacePoint> sites = random_surface_points(m, 16, 7);
  sites[12] = vertex_point(23);
  const int32_t first = 11;
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, t, {});
  const HeatVoronoi old = heat_voronoi(H, m, std::span<const SurfacePoint>(sites.data(), first), {}, {}, {});
  std::vector<int32_t> all(n);
  for (int32_t v = 0; v < n; ++v) all[v] = v;
  HeatVoronoi V = old;
  const std::vector<int32_t> order = {14, 11, 15, 13, 12};
  heat_voronoi_add(H, m, sites, first, std::vector<std::vector<int32_t>>(5, all), order, V, {});
  CHECK(V.batches == old.batches + 1);
  const CscMatrix A = heat_operator(m, t);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) D(A.rowind[p], j) = D(j, A.rowind[p]) = A.values[p];
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(sites.size()));
  for (size_t s = 0; s < sites.size(); ++s) {
    const SurfacePoint& p = sites[s];
    if (p.face < 0) {
      B(p.vertex, s) = 1;
    } else {
      B(m.f0[p.face], s) += p.bary[0];
      B(m.f1[p.face], s) += p.bary[1];
      B(m.f2[p.face], s) += p.bary[2];
    }
  }
  const Eigen::MatrixXd U = D.ldlt().solve(B);
  int32_t changed = 0;
  for (int32_t v = 0; v < n; ++v) {
    std::vector<std::pair<double, int>> row;
    for (int s = 0; s < static_cast<int>(sites.size()); ++s) row.push_back({-U(v, s), s});
    std::sort(row.begin(), row.end());
    CHECK(V.label[v] == row[0].second);
    changed += V.label[v] != old.label[v];
    for (int k = 0; k < kVoronoiTopK; ++k) {
      CHECK(V.top_site[v * kVoronoiTopK + k] == row[k].second);
      CHECK(V.top_value[v * kVoronoiTopK + k] == doctest::Approx(-row[k].first).epsilon(1e-9));
    }
  }
  CHECK(changed > 0);
  // The old diagram with each vertex's hottest entry only (a CVT repair keeps
  // that between its rounds): the same labels and label heat after the add,
  // the dense argmax; the diagram extraction refuses the short lists.
  HeatVoronoi hot = old;
  keep_hottest_only(hot);
  REQUIRE(hot.top_k == 1);
  CHECK(hot.top_site.empty());  // every vertex reached: the hottest sites are the labels
  CHECK_THROWS_AS(extract_voronoi_diagram(H, m, std::span<const SurfacePoint>(sites.data(), first), hot, {}), Error);
  heat_voronoi_add(H, m, sites, first, std::vector<std::vector<int32_t>>(5, all), order, hot, {});
  REQUIRE(hot.top_value.size() == static_cast<size_t>(n));
  CHECK(hot.top_site.empty());
  for (int32_t v = 0; v < n; ++v) {
    double best = -U(v, 0);
    int32_t arg = 0;
    for (int s = 1; s < static_cast<int>(sites.size()); ++s)
      if (U(v, s) > -best) best = -U(v, s), arg = s;
    CHECK(hot.label[v] == arg);
    CHECK(hot.top_value[v] == doctest::Approx(-best).epsilon(1e-9));
  }
  // A vertex no old site reached (labelled by the fallback, its list empty)
  // keeps its empty entry apart from the label: any new site's heat enters
  // there, so its label is the hottest new site (dense argmax over them).
  HeatVoronoi gap = old;
  std::fill_n(gap.top_site.begin(), kVoronoiTopK, -1);
  std::fill_n(gap.top_value.begin(), kVoronoiTopK, 0.0);
  keep_hottest_only(gap);
  REQUIRE(gap.top_site.size() == static_cast<size_t>(n));
  CHECK(gap.top_site[0] == -1);
  CHECK(gap.label[0] == old.label[0]);
  heat_voronoi_add(H, m, sites, first, std::vector<std::vector<int32_t>>(5, all), order, gap, {});
  int32_t arg0 = first;
  for (int s = first + 1; s < static_cast<int>(sites.size()); ++s)
    if (U(0, s) > U(0, arg0)) arg0 = s;
  CHECK(gap.label[0] == arg0);
  CHECK(gap.top_site[0] == arg0);
  CHECK(gap.top_value[0] == doctest::Approx(U(0, arg0)).epsilon(1e-9));
  for (int32_t v = 1; v < n; ++v) CHECK(gap.label[v] == hot.label[v]);
  // Small neighborhoods: vertices outside every new neighborhood keep their label.
  std::vector<std::vector<int32_t>> nb(5);
  std::vector<uint8_t> near(n, 0);
  for (int32_t s = first; s < 16; ++s) {
    const auto p = surface_point_position(m, sites[s]);
    for (int32_t v = 0; v < n; ++v) {
      const double dx = m.x[v] - p[0], dy = m.y[v] - p[1], dz = m.z[v] - p[2];
      if (dx * dx + dy * dy + dz * dz < 0.25) nb[s - first].push_back(v), near[v] = 1;
    }
  }
  HeatVoronoi W = old;
  heat_voronoi_add(H, m, sites, first, nb, {}, W, {});
  for (int32_t v = 0; v < n; ++v)
    if (!near[v]) CHECK(W.label[v] == old.label[v]);
  // Usage errors: a neighborhood missing, an order that is not a permutation of the new ones.
  HeatVoronoi X = old;
  CHECK_THROWS_AS(heat_voronoi_add(H, m, sites, first, std::span(nb.data(), 4), {}, X, {}), Error);
  CHECK_THROWS_AS(heat_voronoi_add(H, m, sites, first, nb, std::vector<int32_t>{11, 12, 13, 14, 14}, X, {}), Error);
  CHECK_THROWS_AS(heat_voronoi_add(H, m, sites, first, nb, std::vector<int32_t>{10, 11, 12, 13, 14}, X, {}), Error);
}
