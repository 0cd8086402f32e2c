// Tests for pipelines/voronoi/skinning_handles (thesis §3.7.2, bones as
// multi-source handles). Oracles: the grid's vertex ids on a line, written down
// from the grid's numbering (id = j*(n+1) + i at (i/n, j/n)); a bone handle's
// weights equal those of the same vertex list given by hand, bit for bit.
#include "locus/pipelines/voronoi/skinning_handles.hpp"

#include <doctest/doctest.h>

#include <array>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"

using namespace locus;

TEST_CASE("bone handle: the vertices nearest to the segment, same weights as the vertex set") {
  const int32_t g = 16;
  const Mesh m = make_grid(g);
  // A bone hovering above the row j = 4 from i = 2 to i = 7.
  const std::array<double, 3> a{2.0 / g, 4.0 / g, 0.01}, b{7.0 / g, 4.0 / g, 0.01};
  const std::vector<std::array<double, 3>> bone{a, b};
  std::vector<int32_t> row;
  for (int32_t i = 2; i <= 7; ++i) row.push_back(4 * (g + 1) + i);
  CHECK(bone_vertices(m, bone) == row);
  std::vector<SkinningHandle> by_bone(3), by_list(3);
  by_bone[0].bone = bone;
  by_list[0].vertices = row;
  for (auto* h : {&by_bone, &by_list}) {
    (*h)[1].vertices = {12 * (g + 1) + 3};
    (*h)[2].vertices = {10 * (g + 1) + 13, 11 * (g + 1) + 13};
  }
  const auto sb = handle_vertex_sets(m, by_bone), sl = handle_vertex_sets(m, by_list);
  CHECK(sb == sl);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});
  for (SkinningMethod method : {SkinningMethod::Sampled, SkinningMethod::Exact}) {
    SkinningOptions o;
    o.method = method;
    o.samples = 60;
    o.exact_up_to = 0;  // the grid is small: keep the sampled road
    const SkinningWeights wb = skinning_weights(H, m, sb, o, {}), wl = skinning_weights(H, m, sl, o, {});
    CHECK(wb.weight == wl.weight);
    for (int32_t v : row) CHECK(wb.weight[static_cast<size_t>(v) * 3] == 1.0);
  }
}

TEST_CASE("skinning handles: overlaps, joints shared by bones, bad input") {
  const Mesh m = make_grid(8);
  std::vector<SkinningHandle> h(2);
  h[0].vertices = {3, 4};
  h[1].vertices = {4, 5};
  CHECK_THROWS_AS(handle_vertex_sets(m, h), Error);  // vertex 4 in two lists
  h[1].vertices = {99};
  CHECK_THROWS_AS(handle_vertex_sets(m, h), Error);  // out of range
  // Two bones meeting at the joint (0.5, 0.5): the joint stays with the first.
  h[0].vertices.clear();
  h[1].vertices.clear();
  h[0].bone = {{0.25, 0.5, 0}, {0.5, 0.5, 0}};
  h[1].bone = {{0.5, 0.5, 0}, {0.5, 0.75, 0}};
  const auto s = handle_vertex_sets(m, h);
  const int32_t joint = 4 * 9 + 4;
  CHECK(std::find(s[0].begin(), s[0].end(), joint) != s[0].end());
  CHECK(std::find(s[1].begin(), s[1].end(), joint) == s[1].end());
  CHECK(s[1] == std::vector<int32_t>{5 * 9 + 4, 6 * 9 + 4});
  h[1].bone = {{0.5, 0.5, 0}};
  CHECK_THROWS_AS(handle_vertex_sets(m, h), Error);  // one point is no bone
  CHECK_THROWS_AS(handle_vertex_sets(m, {}), Error);
}
