// Tests for kernels/mesh/nearest_seed_buckets.{hpp,cpp}: the bucket queue's
// labels against a Bellman-Ford oracle written here (every edge relaxed until
// nothing changes) and against the heap (label_nearest_seeds_by_positions),
// exactly on random spheres (no ties); on a regular grid (many exact ties)
// every label is a seed at the shortest distance.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/nearest_seed_buckets.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"

using namespace locus;

namespace {

double edge(const Mesh& m, int32_t i, int32_t j) {
  return std::sqrt((m.x[j] - m.x[i]) * (m.x[j] - m.x[i]) + (m.y[j] - m.y[i]) * (m.y[j] - m.y[i]) +
                   (m.z[j] - m.z[i]) * (m.z[j] - m.z[i]));
}

// Distances from every seed (per seed label: the shortest over its seeds), by
// Bellman-Ford over the faces' edges.
std::vector<std::vector<double>> oracle_distances(const Mesh& m, const std::vector<GrowSeed>& seeds,
                                                  const std::vector<int32_t>& seed_label, int32_t labels) {
  const int32_t n = m.num_vertices();
  std::vector<std::vector<double>> d(static_cast<size_t>(labels),
                                     std::vector<double>(static_cast<size_t>(n), std::numeric_limits<double>::infinity()));
  for (size_t k = 0; k < seeds.size(); ++k)
    d[seed_label[k]][seeds[k].vertex] = std::min(d[seed_label[k]][seeds[k].vertex], seeds[k].distance);
  for (auto& dl : d)
    for (bool changed = true; changed;) {
      changed = false;
      for (int32_t f = 0; f < m.num_faces(); ++f) {
        const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            if (a != b && dl[v[a]] + edge(m, v[a], v[b]) < dl[v[b]]) {
              dl[v[b]] = dl[v[a]] + edge(m, v[a], v[b]);
              changed = true;
            }
      }
    }
  return d;
}

}  // namespace

TEST_CASE("bucketed seed labels: the heap's labels and the oracle's nearest seed on random spheres") {
  for (uint64_t seed : {3u, 11u}) {
    const Mesh m = make_random_sphere(700, seed);
    const Adjacency adj = vertex_adjacency(m);
    const SeedBucketPlan plan = prepare_seed_buckets(adj, m);
    REQUIRE(plan.usable());
    const std::vector<GrowSeed> seeds = {{3, 0.01}, {40, 0.02}, {41, 0.005}, {250, 0.0}, {477, 0.03}, {100, 0.015}};
    const std::vector<int32_t> seed_label = {0, 0, 0, 1, 2, 2};
    SeedBucketWorkspace ws;
    std::vector<int32_t> got(static_cast<size_t>(m.num_vertices()), 99);
    label_nearest_seeds_bucketed(adj, m, plan, seeds, seed_label, ws, got);
    GrowWorkspace gws;
    std::vector<int32_t> heap(got.size());
    label_nearest_seeds_by_positions(adj, m, seeds, seed_label, gws, heap);
    CHECK(got == heap);
    const auto d = oracle_distances(m, seeds, seed_label, 3);
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
      int32_t want = 0;
      for (int32_t l = 1; l < 3; ++l)
        if (d[l][v] < d[want][v]) want = l;
      CHECK(got[v] == want);
    }
    // The workspace is reusable: a second labelling from other seeds.
    label_nearest_seeds_bucketed(adj, m, plan, std::vector<GrowSeed>{{7, 0.0}}, std::vector<int32_t>{5}, ws, got);
    CHECK(std::all_of(got.begin(), got.end(), [](int32_t l) { return l == 5; }));
  }
}

TEST_CASE("bucketed seed labels: exact ties on a grid, far seeds, unreached vertices, usage errors") {
  Mesh m = make_grid(12);  // equal edges: many vertices at tied distances
  const int32_t n0 = m.num_vertices();
  for (int k = 0; k < 3; ++k) {  // a second, disjoint triangle
    m.x.push_back(50.0 + k);
    m.y.push_back(k == 2 ? 1.0 : 0.0);
    m.z.push_back(0.0);
  }
  m.add_triangle(n0, n0 + 1, n0 + 2);
  const Adjacency adj = vertex_adjacency(m);
  const SeedBucketPlan plan = prepare_seed_buckets(adj, m);
  REQUIRE(plan.usable());
  // One seed far beyond the longest edge: the ring widens for it.
  const std::vector<GrowSeed> seeds = {{0, 0.0}, {n0 - 1, 0.0}, {60, 0.3}, {30, 7.5}};
  const std::vector<int32_t> seed_label = {0, 1, 2, 3};
  SeedBucketWorkspace ws;
  std::vector<int32_t> got(static_cast<size_t>(m.num_vertices()));
  label_nearest_seeds_bucketed(adj, m, plan, seeds, seed_label, ws, got);
  const auto d = oracle_distances(m, seeds, seed_label, 4);
  for (int32_t v = 0; v < n0; ++v) {
    double best = d[0][v];
    for (int32_t l = 1; l < 4; ++l) best = std::min(best, d[l][v]);
    REQUIRE(got[v] >= 0);
    CHECK(d[got[v]][v] == best);
  }
  for (int32_t v = n0; v < n0 + 3; ++v) CHECK(got[v] == -1);
  label_nearest_seeds_bucketed(adj, m, plan, std::vector<GrowSeed>{}, std::vector<int32_t>{}, ws, got);
  CHECK(std::all_of(got.begin(), got.end(), [](int32_t l) { return l == -1; }));
  CHECK_THROWS_AS(label_nearest_seeds_bucketed(adj, m, plan, std::vector<GrowSeed>{{n0 + 3, 0.0}},
                                               std::vector<int32_t>{0}, ws, got),
                  Error);
  CHECK_THROWS_AS(label_nearest_seeds_bucketed(adj, m, plan, std::vector<GrowSeed>{{0, -1.0}}, std::vector<int32_t>{0},
                                               ws, got),
                  Error);
  CHECK_THROWS_AS(
      label_nearest_seeds_bucketed(adj, m, plan, std::vector<GrowSeed>{{0, 0.0}}, std::vector<int32_t>{}, ws, got), Error);
  std::vector<int32_t> short_label(3);
  CHECK_THROWS_AS(label_nearest_seeds_bucketed(adj, m, plan, std::vector<GrowSeed>{{0, 0.0}}, std::vector<int32_t>{0},
                                               ws, short_label),
                  Error);
}

TEST_CASE("bucketed seed labels: no plan for a zero-length edge or a wide spread of lengths") {
  Mesh m = make_grid(4);
  m.x[5] = m.x[6], m.y[5] = m.y[6], m.z[5] = m.z[6];  // an edge of length 0
  const Adjacency adj = vertex_adjacency(m);
  const SeedBucketPlan zero = prepare_seed_buckets(adj, m);
  CHECK_FALSE(zero.usable());
  std::vector<int32_t> label(static_cast<size_t>(m.num_vertices()));
  SeedBucketWorkspace ws;
  CHECK_THROWS_AS(label_nearest_seeds_bucketed(adj, m, zero, std::vector<GrowSeed>{{0, 0.0}}, std::vector<int32_t>{0},
                                               ws, label),
                  Error);
  Mesh wide = make_grid(4);
  wide.x[0] = -1e4;  // edges of 1e4 beside edges of 0.25: beyond kMaxBucketSpread
  CHECK_FALSE(prepare_seed_buckets(vertex_adjacency(wide), wide).usable());
  CHECK_THROWS_AS(prepare_seed_buckets(vertex_adjacency(make_grid(3)), m), Error);  // another mesh's adjacency
}

TEST_CASE("bucketed seed labels: buckets of thousands of vertices, in parallel, are the heap's labels for any threads") {
  // An icosphere's nearly equal edges (jittered: no exact ties) make wide
  // buckets: each holds a good part of a front, hundreds of vertices.
  Mesh m = make_icosphere(6);
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double j = 1 + 1e-3 * std::sin(12.9898 * v);
    m.x[v] *= j, m.y[v] *= j, m.z[v] *= j;
  }
  const Adjacency adj = vertex_adjacency(m);
  const SeedBucketPlan plan = prepare_seed_buckets(adj, m);
  REQUIRE(plan.usable());
  const int32_t n = m.num_vertices();
  const std::vector<GrowSeed> seeds = {{10, 0.0}, {n / 2, 0.001}, {n - 1, 0.002}};
  const std::vector<int32_t> seed_label = {0, 1, 2};
  GrowWorkspace gws;
  std::vector<int32_t> heap(static_cast<size_t>(m.num_vertices()));
  label_nearest_seeds_by_positions(adj, m, seeds, seed_label, gws, heap);
  for (int threads : {1, 2, 4}) {
    CAPTURE(threads);
    tbb::task_arena arena(threads);
    SeedBucketWorkspace ws;
    std::vector<int32_t> got(heap.size(), -7);
    arena.execute([&] { label_nearest_seeds_bucketed(adj, m, plan, seeds, seed_label, ws, got); });
    CHECK(got == heap);
  }
  // Wide buckets (a width near the longest edge): each held most of a front.
  CHECK(plan.buckets < 8);
}
