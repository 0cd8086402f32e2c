// Tests for pipelines/voronoi/skinning_sampled and the Sampled method of
// skinning_weights (thesis §3.7.2: weights on a coarse set, propagated).
// Oracles: an independent breadth-first search for the cover radius; the
// barycentric properties checked entry by entry (non-negative, sum 1, indicator
// on handle vertices); locality against the exact weights through a Euclidean
// ball (which contains the geodesic ball the propagation reads); the difference
// to the exact per-vertex weights; constants reproduced by the propagation.
#include "locus/pipelines/voronoi/skinning_sampled.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"
#include "tests/pipelines/voronoi/extreme_vertex.hpp"

using namespace locus;
using locus::test::extreme_vertex;

namespace {

std::vector<std::vector<int32_t>> five_handles(const Mesh& m) {
  const double dirs[][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  std::vector<std::vector<int32_t>> h;
  for (const auto& d : dirs) h.push_back({extreme_vertex(m, d)});
  return h;
}

}  // namespace

TEST_CASE("cover samples: handle vertices first, every vertex within the radius (independent BFS)") {
  const Mesh m = make_icosphere(3);
  const Adjacency adj = vertex_adjacency(m);
  const int32_t first[] = {17, 5};
  for (int32_t rings : {0, 1, 3}) {
    const std::vector<int32_t> s = cover_samples(adj, first, rings);
    REQUIRE(s.size() >= 2);
    CHECK(s[0] == 17);
    CHECK(s[1] == 5);
    std::vector<int32_t> hops(m.num_vertices(), -1), queue(s.begin(), s.end());
    for (int32_t v : s) hops[v] = 0;
    for (size_t q = 0; q < queue.size(); ++q)
      for (int64_t p = adj.offsets[queue[q]]; p < adj.offsets[queue[q] + 1]; ++p)
        if (hops[adj.neighbors[p]] < 0) {
          hops[adj.neighbors[p]] = hops[queue[q]] + 1;
          queue.push_back(adj.neighbors[p]);
        }
    CHECK(*std::min_element(hops.begin(), hops.end()) == 0);
    CHECK(*std::max_element(hops.begin(), hops.end()) <= rings);
    if (rings == 0) CHECK(s.size() == static_cast<size_t>(m.num_vertices()));
  }
}

TEST_CASE("propagate samples: sample rows kept, a constant row reproduced, convex rows") {
  const Mesh m = make_icosphere(4);
  const Adjacency adj = vertex_adjacency(m);
  const std::vector<int32_t> s = cover_samples(adj, {}, 2);
  const int32_t k = 3, n = m.num_vertices();
  std::vector<double> rows(s.size() * k), out(static_cast<size_t>(n) * k);
  for (size_t i = 0; i < s.size(); ++i) {  // row (z^2, x^2, y^2) of the unit sphere: sums to 1
    rows[i * k] = m.z[s[i]] * m.z[s[i]];
    rows[i * k + 1] = m.x[s[i]] * m.x[s[i]];
    rows[i * k + 2] = std::max(0.0, 1 - rows[i * k] - rows[i * k + 1]);
  }
  const Propagation P = propagate_samples(m, adj, s, rows, {}, k, out, {});
  CHECK(P.radius > 0);
  for (size_t i = 0; i < s.size(); ++i)
    for (int32_t j = 0; j < k; ++j) CHECK(out[static_cast<size_t>(s[i]) * k + j] == rows[i * k + j]);
  double err = 0;
  for (int32_t v = 0; v < n; ++v) {
    double sum = 0;
    for (int32_t j = 0; j < k; ++j) {
      CHECK(out[static_cast<size_t>(v) * k + j] >= 0);
      sum += out[static_cast<size_t>(v) * k + j];
    }
    CHECK(std::abs(sum - 1) <= 1e-12);
    err = std::max(err, std::abs(out[static_cast<size_t>(v) * k] - m.z[v] * m.z[v]));
  }
  CHECK(err < 0.05);  // a smooth function, sampled every 2 rings of a level-4 sphere
}

TEST_CASE("propagate samples: a weight under 1e-3 of its row's largest is 0 off the samples, above it kept") {
  // Every sample has handle 2 at `tiny`: the interpolated value is `tiny` too (a
  // constant is reproduced), so it must come out 0 below the cut, as is above it.
  const Mesh m = make_icosphere(3);
  const Adjacency adj = vertex_adjacency(m);
  const std::vector<int32_t> s = cover_samples(adj, {}, 2);
  const int32_t k = 3, n = m.num_vertices();
  std::vector<uint8_t> is_sample(n, 0);
  for (int32_t v : s) is_sample[v] = 1;
  for (double tiny : {5e-5, 2e-3}) {
    std::vector<double> rows(s.size() * k), out(static_cast<size_t>(n) * k);
    for (size_t i = 0; i < s.size(); ++i) {
      const double z2 = m.z[s[i]] * m.z[s[i]];
      rows[i * k] = 0.6 + 0.4 * z2 - tiny;
      rows[i * k + 1] = 0.4 * (1 - z2);
      rows[i * k + 2] = tiny;
    }
    propagate_samples(m, adj, s, rows, {}, k, out, {});
    int32_t zero = 0, off_samples = 0;
    for (int32_t v = 0; v < n; ++v) {
      const double* w = out.data() + static_cast<size_t>(v) * k;
      CHECK(std::abs(w[0] + w[1] + w[2] - 1) <= 1e-12);
      if (is_sample[v]) {
        CHECK(w[2] == tiny);  // exact rows are not cut
        continue;
      }
      ++off_samples;
      zero += w[2] == 0.0;
      const double top = std::max({w[0], w[1], w[2]});
      for (int32_t j = 0; j < k; ++j) CHECK((w[j] == 0.0 || w[j] >= 1e-3 * top));
    }
    CHECK(off_samples > 0);
    CHECK(zero == (tiny < 1e-3 ? off_samples : 0));
  }
}

TEST_CASE("sampled skinning weights: properties, locality against exact, difference bounds") {
  const Mesh m = make_icosphere(4);
  const int32_t n = m.num_vertices();
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const auto handles = five_handles(m);
  const int32_t k = static_cast<int32_t>(handles.size());
  SkinningOptions exact_o, fast_o;
  exact_o.method = SkinningMethod::Exact;
  fast_o.samples = 700;  // a cover of radius 1 ring (642 samples): genuinely sampled
  fast_o.exact_up_to = 0;
  const SkinningWeights E = skinning_weights(H, m, handles, exact_o, {});
  RunContext one, two;
  one.threads = 1;
  two.threads = 2;
  const SkinningWeights W = skinning_weights(H, m, handles, fast_o, one);
  CHECK(W.weight == skinning_weights(H, m, handles, fast_o, two).weight);  // bitwise, any thread count
  CHECK(W.method == "sampled");
  CHECK(W.samples < n / 3);
  double dmax = 0, dsum = 0;
  for (int32_t v = 0; v < n; ++v) {
    double sum = 0;
    for (int32_t j = 0; j < k; ++j) {
      const double w = W.weight[static_cast<size_t>(v) * k + j];
      CHECK(w >= 0);
      sum += w;
      dmax = std::max(dmax, std::abs(w - E.weight[static_cast<size_t>(v) * k + j]));
      dsum += std::abs(w - E.weight[static_cast<size_t>(v) * k + j]);
    }
    CHECK(std::abs(sum - 1) <= 1e-12);
  }
  for (int32_t j = 0; j < k; ++j)
    for (int32_t i = 0; i < k; ++i) CHECK(W.weight[static_cast<size_t>(handles[j][0]) * k + i] == (i == j ? 1.0 : 0.0));
  // The exact weights of this regular mesh are smooth (neighbours differ by < 0.07):
  // the propagation follows them to the bounds.
  CHECK(dmax <= 0.05);
  CHECK(dsum / (static_cast<double>(n) * k) <= 0.005);
  // Locality: where the exact weight is 0 in the whole Euclidean ball of the
  // propagation radius, the sampled weight is exactly 0.
  int64_t checked = 0;
  for (int32_t v = 0; v < n; v += 7)
    for (int32_t j = 0; j < k; ++j) {
      bool zero_ball = true;
      for (int32_t u = 0; u < n && zero_ball; ++u) {
        const double d = std::hypot(m.x[u] - m.x[v], m.y[u] - m.y[v], m.z[u] - m.z[v]);
        if (d <= W.radius && E.weight[static_cast<size_t>(u) * k + j] != 0.0) zero_ball = false;
      }
      if (!zero_ball) continue;
      ++checked;
      CHECK(W.weight[static_cast<size_t>(v) * k + j] == 0.0);
    }
  CHECK(checked > 0);
}

// Refinement: where the samples around a vertex miss their linear fit, the vertex
// gets its exact row. Oracle: the exact method's rows (bitwise: the same solves
// and cell passes). The weights of this regular mesh are smooth (no vertex is
// refined at the default 0.05): a tolerance of 0.005 on a coarse cover (150
// samples) makes the kinks at the handles and the cells' borders count.
TEST_CASE("sampled skinning weights: refined vertices carry their exact rows, closer to exact than without") {
  const Mesh m = make_icosphere(4);
  const int32_t n = m.num_vertices();
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const auto handles = five_handles(m);
  const int32_t k = static_cast<int32_t>(handles.size());
  SkinningOptions exact_o, on, off;
  exact_o.method = SkinningMethod::Exact;
  on.samples = off.samples = 150;
  on.exact_up_to = 0;
  off.refine_miss = 0;
  on.refine_miss = 0.005;
  const SkinningWeights E = skinning_weights(H, m, handles, exact_o, {});
  const SkinningWeights A = skinning_weights(H, m, handles, off, {});
  const SkinningWeights B = skinning_weights(H, m, handles, on, {});
  CHECK(A.refined == 0);
  CHECK(B.refined > 0);
  CHECK(B.samples == A.samples + B.refined);
  auto row_equal = [&](const SkinningWeights& W, int32_t v) {
    return std::equal(W.weight.begin() + static_cast<size_t>(v) * k, W.weight.begin() + static_cast<size_t>(v + 1) * k,
                      E.weight.begin() + static_cast<size_t>(v) * k);
  };
  int32_t exact_a = 0, exact_b = 0;
  double max_a = 0, max_b = 0, sum_a = 0, sum_b = 0;
  for (int32_t v = 0; v < n; ++v) {
    exact_a += row_equal(A, v);
    exact_b += row_equal(B, v);
    for (int32_t j = 0; j < k; ++j) {
      const size_t a = static_cast<size_t>(v) * k + j;
      max_a = std::max(max_a, std::abs(A.weight[a] - E.weight[a]));
      max_b = std::max(max_b, std::abs(B.weight[a] - E.weight[a]));
      sum_a += std::abs(A.weight[a] - E.weight[a]);
      sum_b += std::abs(B.weight[a] - E.weight[a]);
      CHECK(B.weight[a] >= 0);
    }
  }
  CHECK(exact_b >= exact_a + B.refined);  // every refined row is the exact one
  CHECK(max_b <= max_a);
  CHECK(sum_b < sum_a);
}
