// Tests for pipelines/skinning_weights (thesis §3.7.2, blend skinning).
// Oracles: barycentric-coordinate properties per vertex (non-negative, sum 1,
// indicator at the handles), locality (a handle far from a vertex gets exactly 0),
// agreement with single natural-neighbor queries and, bit for bit, with the
// coordinates of full 8-lane solves, and bitwise equality for 1 and 2 threads.
#include "locus/pipelines/voronoi/skinning_weights.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/error.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"
#include "tests/pipelines/voronoi/extreme_vertex.hpp"

using namespace locus;
using locus::test::extreme_vertex;

TEST_CASE("skinning weights: per-vertex coordinates, indicator at handles, deterministic") {
  const Mesh m = make_icosphere(3);
  const int32_t n = m.num_vertices();
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  // Handles at the vertices nearest to +-x, +-y, +z.
  const double dirs[][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  std::vector<SurfacePoint> handles;
  for (const auto& d : dirs) handles.push_back(vertex_point(extreme_vertex(m, d)));
  RunContext one, two;
  one.threads = 1;
  two.threads = 2;
  const SkinningWeights W = skinning_weights(H, m, handles, one);
  const SkinningWeights W2 = skinning_weights(H, m, handles, two);
  CHECK(W.weight == W2.weight);  // bitwise
  const int32_t k = static_cast<int32_t>(handles.size());
  REQUIRE(W.weight.size() == static_cast<size_t>(n) * k);
  for (int32_t v = 0; v < n; ++v) {
    double sum = 0;
    for (int32_t j = 0; j < k; ++j) {
      CHECK(W.weight[static_cast<size_t>(v) * k + j] >= 0);
      sum += W.weight[static_cast<size_t>(v) * k + j];
    }
    CHECK(sum == doctest::Approx(1).epsilon(1e-12));
  }
  for (int32_t j = 0; j < k; ++j)
    for (int32_t i = 0; i < k; ++i)
      CHECK(W.weight[static_cast<size_t>(handles[j].vertex) * k + i] == (i == j ? 1.0 : 0.0));
  // Locality: near -z (far from the +z handle, whose cell is the cap around it) the +z weight is 0.
  int32_t south = 0;
  for (int32_t v = 0; v < n; ++v)
    if (m.z[v] < m.z[south]) south = v;
  CHECK(W.weight[static_cast<size_t>(south) * k + 4] == 0.0);
  // Same as a one-shot query.
  const NaturalNeighborField F = prepare_natural_neighbors(H, m, handles, {});
  for (int32_t v : {3, 100, 400}) {
    const NaturalCoordinates c = natural_neighbor_coordinates(F, m, vertex_point(v));
    for (int32_t j = 0; j < k; ++j) CHECK(W.weight[static_cast<size_t>(v) * k + j] == doctest::Approx(c.weight[j]).epsilon(1e-12));
  }
  CHECK_THROWS_AS(skinning_weights(H, m, std::vector<SurfacePoint>{vertex_point(n)}, {}), Error);
  // Bit for bit the coordinates of the full 8-lane solve (solve8) of the same
  // batches of 8 vertices: the exact rows' solves (3 batches per pass over the
  // factor, the forward substitution over the sources' etree paths only) change
  // no value.
  std::vector<double> b8(static_cast<size_t>(n) * kLanes);
  std::vector<NaturalCoordinates> c8(kLanes);
  NaturalScratch scratch;
  int32_t differ = 0;
  for (int32_t first = 0; first < n; first += kLanes) {
    const int lanes = std::min<int32_t>(kLanes, n - first);
    std::fill(b8.begin(), b8.end(), 0.0);
    std::vector<SurfacePoint> q;
    for (int l = 0; l < lanes; ++l) {
      b8[static_cast<size_t>(first + l) * kLanes + l] = 1.0;
      q.push_back(vertex_point(first + l));
    }
    solve8(H.factor, b8);
    natural_neighbor_coordinates8(F, m, q, b8, scratch, c8);
    for (int l = 0; l < lanes; ++l)
      for (int32_t j = 0; j < k; ++j) differ += W.weight[static_cast<size_t>(first + l) * k + j] != c8[l].weight[j];
  }
  CHECK(differ == 0);
}

// Smoothness of the exact weights on a regular mesh (icosphere level 4, five
// handles at the extreme vertices): the largest jump of a weight across one edge,
// and the coordinates of a point moving along an edge (no jump inside a triangle).
// Oracle: the bound of a Lipschitz function: on a unit sphere of edge length h a
// weight that falls from 1 to 0 over a handle's cell (radius ~0.8) changes by about
// h / 0.8 = 0.08 per edge; a point moving by a tenth of an edge, by a tenth of that.
TEST_CASE("skinning weights: exact weights smooth on a regular mesh (edge jumps, a point moving along an edge)") {
  const Mesh m = make_icosphere(4);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  const double dirs[][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  std::vector<SurfacePoint> handles;
  for (const auto& d : dirs) handles.push_back(vertex_point(extreme_vertex(m, d)));
  const int32_t k = static_cast<int32_t>(handles.size());
  const SkinningWeights W = skinning_weights(H, m, handles, {});
  CHECK(W.degenerate == 0);
  double jump = 0, h = 0;
  int64_t edges = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int a = 0; a < 3; ++a) {
      const int32_t p = v[a], q = v[(a + 1) % 3];
      h += std::hypot(m.x[p] - m.x[q], m.y[p] - m.y[q], m.z[p] - m.z[q]);
      ++edges;
      for (int32_t j = 0; j < k; ++j)
        jump = std::max(jump, std::abs(W.weight[static_cast<size_t>(p) * k + j] - W.weight[static_cast<size_t>(q) * k + j]));
    }
  }
  h /= static_cast<double>(edges);
  CHECK(jump > 0);          // the weights do vary
  CHECK(jump <= h / 0.8);   // ~0.08 at h ~ 0.063
  // A point moving along the edges of a few faces: steps of h/10, changes <= h/8.
  const NaturalNeighborField F = prepare_natural_neighbors(H, m, handles, {});
  for (int32_t f : {0, 1000, 2500, 4000}) {
    std::vector<double> prev;
    for (int s = 0; s <= 10; ++s) {
      SurfacePoint q;
      q.face = f;
      q.bary = {1 - s / 10.0, s / 10.0, 0};
      const NaturalCoordinates c = natural_neighbor_coordinates(F, m, q);
      if (!prev.empty())
        for (int32_t j = 0; j < k; ++j) CHECK(std::abs(c.weight[j] - prev[j]) <= h / 8);
      prev = c.weight;
    }
  }
}
