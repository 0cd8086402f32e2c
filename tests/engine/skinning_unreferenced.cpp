// Skinning weights on a mesh with a vertex in no face (engine/src/
// session_skinning_command.cpp, pipelines/src/voronoi/skinning_sampled.cpp):
// the outside convention, NaN there; elsewhere the natural-neighbour
// properties (non-negative, a partition of unity, 1 at a handle's vertices).
#include <doctest/doctest.h>

#include <cmath>

#include "locus/engine/skinning_requests.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/session.hpp"

using namespace locus;

TEST_CASE("skinning weights: a vertex in no face gets NaN, the others the natural-neighbour properties") {
  Mesh lone = make_icosphere(3);
  const int32_t n = lone.num_vertices(), k = 4;
  lone.add_vertex(3.0, 0.0, 0.0);
  SkinningRequest q;
  q.handles = {{0}, {100}, {300}, {600}};
  const SkinningReport r = Session(Mesh(lone)).skinning(q);  // auto: the robust operator
  REQUIRE(r.weight.size() == static_cast<size_t>(n + 1) * k);
  for (int j = 0; j < k; ++j) CHECK(std::isnan(r.weight[static_cast<size_t>(n) * k + j]));
  bool non_negative = true;
  double worst_sum = 0;
  for (int32_t v = 0; v < n; ++v) {
    double sum = 0;
    for (int j = 0; j < k; ++j) {
      const double w = r.weight[static_cast<size_t>(v) * k + j];
      non_negative = non_negative && w >= 0.0;
      sum += w;
    }
    worst_sum = std::max(worst_sum, std::abs(sum - 1.0));
  }
  CHECK(non_negative);
  CHECK(worst_sum < 1e-12);
  for (int j = 0; j < k; ++j) {
    const int32_t h = static_cast<int32_t>(q.handles[j][0]);
    for (int i = 0; i < k; ++i) CHECK(r.weight[static_cast<size_t>(h) * k + i] == (i == j ? 1.0 : 0.0));
  }
}
