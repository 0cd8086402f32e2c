// Tests for pipelines/skinning_weights (thesis §3.7.2, blend skinning).
// Oracles: barycentric-coordinate properties per vertex (non-negative, sum 1,
// indicator at the handles), locality (a handle far from a vertex gets exactly 0),
// agreement with single natural-neighbor queries, and bitwise equality for 1 and 2
// threads.
#include "locus/pipelines/voronoi/skinning_weights.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"

using namespace locus;

TEST_CASE("skinning weights: per-vertex coordinates, indicator at handles, deterministic") {
  const Mesh m = make_icosphere(3);
  const int32_t n = m.num_vertices();
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  // Handles at the vertices nearest to +-x, +-y, +z.
  const double dirs[][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  std::vector<SurfacePoint> handles;
  for (const auto& d : dirs) {
    int32_t best = 0;
    for (int32_t v = 0; v < n; ++v)
      if (m.x[v] * d[0] + m.y[v] * d[1] + m.z[v] * d[2] > m.x[best] * d[0] + m.y[best] * d[1] + m.z[best] * d[2]) best = v;
    handles.push_back(vertex_point(best));
  }
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
}
