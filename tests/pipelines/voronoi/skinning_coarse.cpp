// Tests for pipelines/voronoi/skinning_coarse (thesis §3.7.2: weights on a
// coarse mesh, propagated to the vertices). Oracles: the barycentric
// properties checked entry by entry (non-negative, sum 1, indicator on handle
// vertices); the exact per-vertex weights of the fine mesh (difference and
// locality: no weight where the exact weights of a vertex's whole two-ring
// neighbourhood are zero); a single handle's constant weight.
#include "locus/pipelines/voronoi/skinning_coarse.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "tests/pipelines/voronoi/extreme_vertex.hpp"

using namespace locus;
using locus::test::extreme_vertex;

TEST_CASE("coarse skinning weights: properties, close to the exact weights, local") {
  const Mesh m = make_icosphere(4);
  const int32_t n = m.num_vertices();
  const double dirs[][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  std::vector<std::vector<int32_t>> handles;
  for (const auto& d : dirs) handles.push_back({extreme_vertex(m, d)});
  const int32_t k = static_cast<int32_t>(handles.size());
  const SkinningWeights W = skinning_weights_coarse(m, handles, {}, 1.0, 0.0, {});
  CHECK(W.method == "coarse");
  CHECK(W.coarse_vertices > k);
  CHECK(W.coarse_vertices < n / 2);
  REQUIRE(W.weight.size() == static_cast<size_t>(n) * k);
  for (int32_t v = 0; v < n; ++v) {
    double sum = 0;
    for (int32_t j = 0; j < k; ++j) {
      CHECK(W.weight[static_cast<size_t>(v) * k + j] >= 0.0);
      sum += W.weight[static_cast<size_t>(v) * k + j];
    }
    CHECK(std::abs(sum - 1) <= 1e-12);
  }
  for (int32_t j = 0; j < k; ++j)
    for (int32_t i = 0; i < k; ++i) CHECK(W.weight[static_cast<size_t>(handles[j][0]) * k + i] == (i == j ? 1.0 : 0.0));
  // The exact weights of the fine mesh.
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  SkinningOptions exact;
  exact.method = SkinningMethod::Exact;
  const SkinningWeights E = skinning_weights(H, m, handles, exact, {});
  double max_d = 0, sum_d = 0;
  for (size_t i = 0; i < E.weight.size(); ++i) {
    max_d = std::max(max_d, std::abs(E.weight[i] - W.weight[i]));
    sum_d += std::abs(E.weight[i] - W.weight[i]);
  }
  MESSAGE("coarse vs exact: max " << max_d << ", mean " << sum_d / E.weight.size());
  CHECK(max_d < 0.06);
  CHECK(sum_d / E.weight.size() < 0.004);
  // Locality: where the exact weight is 0 on a vertex's whole two-ring, so is the coarse one.
  const Adjacency adj = vertex_adjacency(m);
  int64_t far = 0, outside = 0;
  for (int32_t v = 0; v < n; ++v)
    for (int32_t j = 0; j < k; ++j) {
      bool zero = E.weight[static_cast<size_t>(v) * k + j] == 0.0;
      for (int64_t p = adj.offsets[v]; zero && p < adj.offsets[v + 1]; ++p) {
        const int32_t w = adj.neighbors[p];
        for (int64_t q = adj.offsets[w]; zero && q < adj.offsets[w + 1]; ++q)
          zero = E.weight[static_cast<size_t>(adj.neighbors[q]) * k + j] == 0.0;
        zero = zero && E.weight[static_cast<size_t>(w) * k + j] == 0.0;
      }
      if (!zero) continue;
      ++far;
      outside += W.weight[static_cast<size_t>(v) * k + j] > 0.0;
    }
  CHECK(far > n / 4);  // the test has zeros to check
  CHECK(outside == 0);
}

TEST_CASE("coarse skinning weights: one handle weighs 1 everywhere; a vertex-set handle keeps its indicator") {
  const Mesh m = make_icosphere(3);
  const int32_t n = m.num_vertices();
  const double up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
  const int32_t a = extreme_vertex(m, up), b = extreme_vertex(m, down);
  const std::vector<std::vector<int32_t>> one = {{a}};
  const SkinningWeights W1 = skinning_weights_coarse(m, one, {}, 1.0, 0.0, {});
  for (int32_t v = 0; v < n; ++v) CHECK(W1.weight[v] == 1.0);
  const Adjacency adj = vertex_adjacency(m);
  std::vector<std::vector<int32_t>> two = {{a}, {b}};
  for (int64_t p = adj.offsets[b]; p < adj.offsets[b + 1]; ++p) two[1].push_back(adj.neighbors[p]);
  const SkinningWeights W2 = skinning_weights_coarse(m, two, {}, 1.0, 0.0, {});
  for (int32_t v : two[1]) {
    CHECK(W2.weight[static_cast<size_t>(v) * 2] == 0.0);
    CHECK(W2.weight[static_cast<size_t>(v) * 2 + 1] == 1.0);
  }
  CHECK(W2.weight[static_cast<size_t>(a) * 2] == 1.0);
}
