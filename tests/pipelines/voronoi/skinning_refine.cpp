// Tests for pipelines/voronoi/skinning_refine and the roads of the Sampled method
// of skinning_weights (thesis §3.7.2). Oracles: the exact method's rows (bitwise:
// the same solves and cell passes), the barycentric properties entry by entry.
#include "locus/pipelines/voronoi/skinning_refine.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "tests/pipelines/voronoi/extreme_vertex.hpp"

using namespace locus;
using locus::test::extreme_vertex;

namespace {

std::vector<std::vector<int32_t>> four_handles(const Mesh& m) {
  const double dirs[][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
  std::vector<std::vector<int32_t>> h;
  for (const auto& d : dirs) h.push_back({extreme_vertex(m, d)});
  return h;
}

}  // namespace

// A mesh of at most exact_up_to vertices or 3 x the sample target takes exact
// rows everywhere: the weights are the exact method's, bit for bit; without
// refinement it stays sampled.
TEST_CASE("sampled skinning weights: a small mesh takes the exact rows") {
  const Mesh m = make_icosphere(3);  // 642 vertices
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const auto handles = four_handles(m);
  SkinningOptions exact_o, small_o, plain_o, by_size;
  exact_o.method = SkinningMethod::Exact;
  small_o.samples = 214;  // 3 x 214 = 642
  small_o.exact_up_to = 0;
  plain_o.samples = 214;
  plain_o.refine_miss = 0;
  by_size.samples = 100;  // 3 x 100 < 642, but 642 <= exact_up_to (default 10,000)
  const SkinningWeights Z = skinning_weights(H, m, handles, by_size, {});
  CHECK(Z.method == "exact");
  CHECK(Z.samples == m.num_vertices());
  by_size.exact_up_to = 642;
  CHECK(skinning_weights(H, m, handles, by_size, {}).method == "exact");
  by_size.exact_up_to = 641;
  CHECK(skinning_weights(H, m, handles, by_size, {}).method == "sampled");
  by_size.exact_up_to = -1;
  CHECK_THROWS_AS(skinning_weights(H, m, handles, by_size, {}), Error);
  const SkinningWeights E = skinning_weights(H, m, handles, exact_o, {});
  const SkinningWeights S = skinning_weights(H, m, handles, small_o, {});
  CHECK(S.method == "exact");
  CHECK(S.samples == m.num_vertices());
  CHECK(S.weight == E.weight);
  CHECK(Z.weight == E.weight);
  const SkinningWeights P = skinning_weights(H, m, handles, plain_o, {});
  CHECK(P.method == "sampled");
  CHECK(P.samples < m.num_vertices());
  small_o.samples = 213;  // 3 x 213 < 642: the sampled road
  CHECK(skinning_weights(H, m, handles, small_o, {}).method == "sampled");
}

// With refinement on a coarse cover, the weights are the same for any thread
// count, every refined row is the exact one, and the properties hold.
TEST_CASE("sampled skinning weights: refinement deterministic, refined rows exact, properties") {
  const Mesh m = make_icosphere(4);
  const int32_t n = m.num_vertices();
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const auto handles = four_handles(m);
  const int32_t k = static_cast<int32_t>(handles.size());
  SkinningOptions exact_o, on;
  exact_o.method = SkinningMethod::Exact;
  on.samples = 150;
  on.refine_miss = 0.01;
  on.exact_up_to = 0;  // 2,562 vertices: the sampled road
  RunContext one, two;
  one.threads = 1;
  two.threads = 2;
  const SkinningWeights E = skinning_weights(H, m, handles, exact_o, {});
  const SkinningWeights A = skinning_weights(H, m, handles, on, one);
  const SkinningWeights B = skinning_weights(H, m, handles, on, two);
  CHECK(A.method == "sampled");
  CHECK(A.refined > 0);
  CHECK(A.weight == B.weight);
  CHECK(A.refined == B.refined);
  int32_t exact_rows = 0;
  double worst_sum = 0;
  bool non_negative = true;
  for (int32_t v = 0; v < n; ++v) {
    exact_rows += std::equal(A.weight.begin() + static_cast<size_t>(v) * k,
                             A.weight.begin() + static_cast<size_t>(v + 1) * k, E.weight.begin() + static_cast<size_t>(v) * k);
    double sum = 0;
    for (int32_t j = 0; j < k; ++j) {
      non_negative = non_negative && A.weight[static_cast<size_t>(v) * k + j] >= 0;
      sum += A.weight[static_cast<size_t>(v) * k + j];
    }
    worst_sum = std::max(worst_sum, std::abs(sum - 1));
  }
  CHECK(exact_rows >= A.samples);  // cover samples and refined rows are exact rows
  CHECK(non_negative);
  CHECK(worst_sum <= 1e-12);
  for (int32_t j = 0; j < k; ++j)
    for (int32_t i = 0; i < k; ++i) CHECK(A.weight[static_cast<size_t>(handles[j][0]) * k + i] == (i == j ? 1.0 : 0.0));
}

// The minmod correction on a path 0-1-...-6 with k = 3, every propagated row
// (0.5, 0.5, 0); exact rows at 1 (residual (+0.02, -0.1, +0.08)), 3 (+0.05, -0.05,
// 0) and 5 (-0.05, +0.05, 0). Oracle: the rule by hand, vertex by vertex (the
// exact rows within 2 edges; per weight the residual of least magnitude where all
// agree in sign, else 0; weights at 0 stay 0; the larger side of gains and losses
// scaled to the other's total).
TEST_CASE("correct propagated rows: minmod of the exact rows' residuals within 2 rings, by hand") {
  const int32_t n = 7, k = 3;
  Adjacency adj;
  adj.offsets.assign(n + 1, 0);
  for (int32_t v = 0; v < n; ++v) {
    if (v > 0) adj.neighbors.push_back(v - 1);
    if (v + 1 < n) adj.neighbors.push_back(v + 1);
    adj.offsets[v + 1] = static_cast<int64_t>(adj.neighbors.size());
  }
  std::vector<double> interp;
  for (int32_t v = 0; v < n; ++v) interp.insert(interp.end(), {0.5, 0.5, 0.0});
  SkinningWeights W;
  W.handles = k;
  W.weight = interp;
  const double exact_rows[3][3] = {{0.52, 0.4, 0.08}, {0.55, 0.45, 0.0}, {0.45, 0.55, 0.0}};
  const int32_t at[3] = {1, 3, 5};
  std::vector<uint8_t> exact(n, 0);
  for (int i = 0; i < 3; ++i) {
    exact[at[i]] = 1;
    std::copy_n(exact_rows[i], k, W.weight.begin() + at[i] * k);
  }
  correct_propagated_rows(adj, exact, interp, W);
  auto check = [&](int32_t v, double a, double b) {
    CAPTURE(v);
    CHECK(W.weight[v * k] == doctest::Approx(a).epsilon(1e-14));
    CHECK(W.weight[v * k + 1] == doctest::Approx(b).epsilon(1e-14));
    CHECK(W.weight[v * k + 2] == 0.0);  // 0 where propagated 0, whatever the residuals
  };
  check(0, 0.52, 0.48);  // only 1: (+0.02, -0.1) on the positive weights, the loss scaled to 0.02
  check(2, 0.52, 0.48);  // 1 and 3: weight 0 +0.02, +0.05 -> +0.02; weight 1 -0.1, -0.05 -> -0.05, scaled to -0.02
  check(4, 0.5, 0.5);                // 3 and 5 disagree in sign: unchanged
  check(6, 0.45, 0.55);              // only 5 (4 is not exact)
  for (int i = 0; i < 3; ++i)           // exact rows untouched
    for (int32_t j = 0; j < k; ++j) CHECK(W.weight[at[i] * k + j] == exact_rows[i][j]);
  exact.pop_back();
  CHECK_THROWS_AS(correct_propagated_rows(adj, exact, interp, W), Error);  // one flag short
}

// The zeros step on a path 0-1-2-3-4 with k = 3: rows 0 (exact) (1, 0, 0),
// 1 (0.995, 0.005, 0), 2 (0.5, 0.5, 0), 3 (0.005, 0.005, 0.99), 4 (0, 0, 1), not a
// zero source (a handle's indicator). Oracle: the rule by hand (a weight in
// (0, 0.01) goes where a zero source next to it has it 0, from the rows as they
// came in; rows renormalized, a row that would lose every weight kept).
TEST_CASE("keep neighbour zeros: tiny weights next to a zero, by hand") {
  const int32_t n = 5, k = 3;
  Adjacency adj;
  adj.offsets.assign(n + 1, 0);
  for (int32_t v = 0; v < n; ++v) {
    if (v > 0) adj.neighbors.push_back(v - 1);
    if (v + 1 < n) adj.neighbors.push_back(v + 1);
    adj.offsets[v + 1] = static_cast<int64_t>(adj.neighbors.size());
  }
  SkinningWeights W;
  W.handles = k;
  W.weight = {1, 0, 0, 0.995, 0.005, 0, 0.5, 0.5, 0, 0.005, 0.005, 0.99, 0, 0, 1};
  const std::vector<uint8_t> exact = {1, 0, 0, 0, 1}, source = {1, 1, 1, 1, 0};
  keep_neighbour_zeros(adj, exact, source, 0.01, W);
  const std::vector<double> want = {1, 0, 0,                     // exact: untouched
                                    1, 0, 0,                     // 0.005 next to 0's 0: gone, 0.995 / 0.995
                                    0.5, 0.5, 0,                 // no weight in (0, 0.01)
                                    0.005, 0.005, 0.99,          // 2 has neither weight at 0; 4 is no source
                                    0, 0, 1};
  for (size_t i = 0; i < want.size(); ++i) CHECK(W.weight[i] == doctest::Approx(want[i]).epsilon(1e-15));
  W.weight = {0, 0, 1, 0.004, 0.006, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1};  // 1: both weights would go
  const std::vector<uint8_t> exact2 = {0, 0, 1, 1, 1}, all = {1, 1, 1, 1, 1}, short_flags = {0, 0};
  keep_neighbour_zeros(adj, exact2, all, 0.01, W);
  CHECK(W.weight[3] == 0.004);
  CHECK(W.weight[4] == 0.006);
  CHECK(W.weight[0] == 0.0);  // row 0: its weight 1.0 is not below 0.01
  CHECK(W.weight[2] == 1.0);
  CHECK_THROWS_AS(keep_neighbour_zeros(adj, short_flags, source, 0.01, W), Error);
}

// Corners under the angle: a right triangle with legs 1 and 0.1 has angles 90,
// atan(0.1) = 5.71 and 84.29 degrees; an equilateral one 60 everywhere.
TEST_CASE("skinny corners: the corners under the angle, by the analytic angles") {
  Mesh m;
  m.add_vertex(0, 0, 0);
  m.add_vertex(1, 0, 0);
  m.add_vertex(0, 0.1, 0);
  m.add_vertex(2, 0, 0);
  m.add_vertex(3, 0, 0);
  m.add_vertex(2.5, std::sqrt(0.75), 0);
  m.add_triangle(0, 1, 2);
  m.add_triangle(3, 4, 5);
  CHECK(skinny_corners(m, 5.0).empty());
  CHECK(skinny_corners(m, 10.0) == std::vector<int32_t>{1});
  CHECK(skinny_corners(m, 60.5) == std::vector<int32_t>{1, 3, 4, 5});
  CHECK(skinny_corners(m, 85.0) == std::vector<int32_t>{1, 2, 3, 4, 5});
  CHECK(skinny_corners(m, 90.5) == std::vector<int32_t>{0, 1, 2, 3, 4, 5});
}
