// Tests for pipelines/voronoi/skinning_refine and the roads of the Sampled method
// of skinning_weights (thesis §3.7.2). Oracles: the exact method's rows (bitwise:
// the same solves and cell passes), the barycentric properties entry by entry.
#include "locus/pipelines/voronoi/skinning_refine.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

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

// A mesh of at most 3 x the sample target takes exact rows everywhere: the
// weights are the exact method's, bit for bit; without refinement it stays sampled.
TEST_CASE("sampled skinning weights: a small mesh takes the exact rows") {
  const Mesh m = make_icosphere(3);  // 642 vertices
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const auto handles = four_handles(m);
  SkinningOptions exact_o, small_o, plain_o;
  exact_o.method = SkinningMethod::Exact;
  small_o.samples = 214;  // 3 x 214 = 642
  plain_o.samples = 214;
  plain_o.refine_miss = 0;
  const SkinningWeights E = skinning_weights(H, m, handles, exact_o, {});
  const SkinningWeights S = skinning_weights(H, m, handles, small_o, {});
  CHECK(S.method == "exact");
  CHECK(S.samples == m.num_vertices());
  CHECK(S.weight == E.weight);
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
