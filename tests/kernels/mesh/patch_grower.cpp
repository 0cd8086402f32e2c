// Tests for kernels/mesh/patch_grower.{hpp,cpp}. Oracles written here, from the
// faces alone: a plain BFS over std::set neighbor lists, and an O(n^2) Dijkstra
// (linear scan for the nearest unsettled vertex) on the same edge-length formula.
// Geodesic order is compared exactly on meshes without distance ties (random
// spheres); on a regular grid (many ties) the order must be non-decreasing in
// distance and the set must be the nearest vertices. The labels of a
// multi-source Dijkstra (label_nearest_seeds) against Bellman-Ford.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"

using namespace locus;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<std::set<int32_t>> neighbor_sets(const Mesh& m) {
  std::vector<std::set<int32_t>> nb(static_cast<size_t>(m.num_vertices()));
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (a != b) nb[v[a]].insert(v[b]);
  }
  return nb;
}

double edge(const Mesh& m, int32_t i, int32_t j) {  // neighbor j minus vertex i, as the grower documents
  return std::sqrt((m.x[j] - m.x[i]) * (m.x[j] - m.x[i]) + (m.y[j] - m.y[i]) * (m.y[j] - m.y[i]) +
                   (m.z[j] - m.z[i]) * (m.z[j] - m.z[i]));
}

// BFS: seed first, FIFO, neighbors ascending; the first `count` vertices and their depths.
std::vector<int32_t> oracle_bfs(const Mesh& m, int32_t seed, int32_t count, int32_t* rings) {
  const auto nb = neighbor_sets(m);
  std::vector<int32_t> depth(static_cast<size_t>(m.num_vertices()), -1), order{seed};
  depth[seed] = 0;
  for (size_t h = 0; h < order.size(); ++h)
    for (int32_t w : nb[order[h]])
      if (depth[w] < 0) {
        depth[w] = depth[order[h]] + 1;
        order.push_back(w);
      }
  if (static_cast<int32_t>(order.size()) > count) order.resize(static_cast<size_t>(count));
  *rings = 0;
  for (int32_t v : order) *rings = std::max(*rings, depth[v]);
  return order;
}

// O(n^2) Dijkstra from seeds with initial distances; returns the final distances
// and the settle order (ties: lowest id, which only matters on tied meshes).
std::vector<double> oracle_dijkstra(const Mesh& m, const std::vector<GrowSeed>& seeds, std::vector<int32_t>& order) {
  const int32_t n = m.num_vertices();
  const auto nb = neighbor_sets(m);
  std::vector<double> d(static_cast<size_t>(n), kInf);
  std::vector<char> done(static_cast<size_t>(n), 0);
  for (const GrowSeed& s : seeds) d[s.vertex] = std::min(d[s.vertex], s.distance);
  order.clear();
  for (;;) {
    int32_t best = -1;
    for (int32_t v = 0; v < n; ++v)
      if (!done[v] && d[v] < kInf && (best < 0 || d[v] < d[best])) best = v;
    if (best < 0) break;
    done[best] = 1;
    order.push_back(best);
    for (int32_t w : nb[best])
      if (!done[w]) d[w] = std::min(d[w], d[best] + edge(m, best, w));
  }
  return d;
}

std::vector<int32_t> grow(const PatchGrower& g, std::vector<GrowSeed> seeds, const GrowOptions& o, GrowWorkspace& ws) {
  std::vector<int32_t> out;
  grow_vertices(g.adjacency, g.edge_length, seeds, o, ws, out);
  return out;
}

}  // namespace

TEST_CASE("patch grower, Rings: the BFS order, truncated at the count; depth reached") {
  const Mesh m = make_random_sphere(600, 3);
  const PatchGrower g = prepare_patch_grower(m);
  GrowWorkspace ws;  // reused: the workspace must be clean after every grow
  for (int32_t seed : {0, 17, 599})
    for (int32_t count : {1, 2, 7, 50, 333, 600, 5000}) {
      CAPTURE(seed);
      CAPTURE(count);
      int32_t rings = -1;
      const std::vector<int32_t> want = oracle_bfs(m, seed, count, &rings);
      std::vector<int32_t> got;
      const int32_t got_rings = grow_vertices(g.adjacency, {}, std::vector<GrowSeed>{{seed, 0.0}}, ring_patch(count), ws, got);
      CHECK(got == want);
      CHECK(got_rings == rings);
      CHECK(grow_ring_vertices(g.adjacency, seed, count) == want);
    }
  CHECK(grow_ring_vertices(g.adjacency, 5, 0) == std::vector<int32_t>{5});
}

TEST_CASE("patch grower, Geodesic: the Dijkstra order on a mesh without ties") {
  const Mesh m = make_random_sphere(700, 9);
  const PatchGrower g = prepare_patch_grower(m);
  GrowWorkspace ws;
  for (int32_t c : {0, 123, 699}) {
    std::vector<int32_t> order;
    const std::vector<double> d = oracle_dijkstra(m, {{c, 0.0}}, order);
    for (int32_t count : {1, 3, 100, 700, 900}) {
      CAPTURE(c);
      CAPTURE(count);
      std::vector<int32_t> want(order.begin(), order.begin() + std::min<size_t>(order.size(), count));
      CHECK(grow(g, {{c, 0.0}}, geodesic_disk(count), ws) == want);
    }
    // StopBeyond: exactly the vertices within the radius, in order.
    for (double r : {0.0, 0.1, 0.35, 10.0}) {
      GrowOptions o = geodesic_disk(1 << 30);
      o.max_radius = r;
      std::vector<int32_t> want;
      for (int32_t v : order)
        if (d[v] <= r) want.push_back(v);
      CHECK(grow(g, {{c, 0.0}}, o, ws) == want);
    }
  }
}

TEST_CASE("patch grower, Geodesic: several seeds, PruneBeyond keeps far seeds") {
  const Mesh m = make_random_sphere(500, 21);
  const PatchGrower g = prepare_patch_grower(m);
  GrowWorkspace ws;
  const std::vector<GrowSeed> seeds{{10, 0.05}, {200, 0.0}, {10, 0.02}, {301, 0.4}};  // 10 repeated: 0.02 counts
  std::vector<int32_t> order;
  const std::vector<double> d = oracle_dijkstra(m, seeds, order);
  CHECK(d[10] == 0.02);
  // Unlimited: everything, in the oracle's order.
  CHECK(grow(g, seeds, geodesic_disk(1 << 30), ws) == order);
  GrowOptions o = geodesic_disk(1 << 30);
  o.max_radius = 0.25;
  o.radius_rule = RadiusRule::PruneBeyond;
  std::vector<int32_t> got = grow(g, seeds, o, ws);
  std::vector<int32_t> want;
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (d[v] <= 0.25 || v == 301) want.push_back(v);  // seed 301 (0.4) is kept though beyond the radius
  std::sort(got.begin(), got.end());
  CHECK(got == want);
  CHECK(d[301] > 0.25);                    // the far seed is far (else the case tests nothing)
  o.radius_rule = RadiusRule::StopBeyond;  // the same set without the far seed, in distance order
  got = grow(g, seeds, o, ws);
  want.clear();
  for (int32_t v : order)
    if (d[v] <= 0.25) want.push_back(v);
  CHECK(got == want);
}

TEST_CASE("patch grower, Geodesic on a regular grid (ties): distance order, nearest set") {
  const Mesh m = make_grid(12);
  const PatchGrower g = prepare_patch_grower(m);
  GrowWorkspace ws;
  const int32_t c = m.num_vertices() / 2;
  std::vector<int32_t> order;
  const std::vector<double> d = oracle_dijkstra(m, {{c, 0.0}}, order);
  for (int32_t count : {5, 40, 100}) {
    const std::vector<int32_t> got = grow(g, {{c, 0.0}}, geodesic_disk(count), ws);
    REQUIRE(static_cast<int32_t>(got.size()) == count);
    CHECK(got[0] == c);
    for (size_t k = 1; k < got.size(); ++k) CHECK(d[got[k - 1]] <= d[got[k]]);
    std::vector<double> sorted = d;
    std::sort(sorted.begin(), sorted.end());
    for (int32_t v : got) CHECK(d[v] <= sorted[count - 1]);
    CHECK(std::set<int32_t>(got.begin(), got.end()).size() == got.size());
  }
}

TEST_CASE("patch grower: grow_patch assembles the selected vertices; usage errors") {
  const Mesh m = make_random_sphere(400, 5);
  const PatchGrower g = prepare_patch_grower(m);
  PatchWorkspace pws;
  for (const GrowOptions& o : {ring_patch(60), geodesic_disk(60)}) {
    std::vector<int32_t> sel;
    grow_patch_vertices(g, 7, o, pws, sel);
    const MeshPatch p = grow_patch(g, 7, o, pws);
    const MeshPatch e = extract_patch(g, sel, pws);
    CHECK(p.vertices == e.vertices);
    CHECK(p.faces == e.faces);
    CHECK(p.vertices.front() == 7);
    CHECK(p.mesh.num_faces() == static_cast<int32_t>(p.faces.size()));
    for (int32_t v : pws.local) REQUIRE(v == -1);
  }
  GrowWorkspace ws;
  std::vector<int32_t> out;
  const auto code = [](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::Internal;  // did not throw
  };
  CHECK(code([&] { grow_vertices(g.adjacency, g.edge_length, std::vector<GrowSeed>{}, ring_patch(3), ws, out); }) ==
        ErrorCode::BadUsage);
  CHECK(code([&] { grow_vertices(g.adjacency, g.edge_length, std::vector<GrowSeed>{{400, 0}}, ring_patch(3), ws, out); }) ==
        ErrorCode::BadUsage);
  CHECK(code([&] { grow_vertices(g.adjacency, g.edge_length, std::vector<GrowSeed>{{0, 0}}, ring_patch(0), ws, out); }) ==
        ErrorCode::BadUsage);
  CHECK(code([&] { grow_vertices(g.adjacency, {}, std::vector<GrowSeed>{{0, 0}}, geodesic_disk(3), ws, out); }) ==
        ErrorCode::BadUsage);
  CHECK(code([&] { prepare_patch_grower(make_quad_torus(4, 4)); }) == ErrorCode::BadInput);
  CHECK(patch_vertex_count(400, 0.1) == 40);
}

namespace {

// Multi-source shortest paths by Bellman-Ford over the undirected edges (relax
// every edge both ways until nothing changes), each vertex labelled by the seed
// its shortest path starts from. No heap, no settle order: an oracle for the
// labels on meshes without distance ties.
void oracle_bellman_ford(const Mesh& m, const std::vector<GrowSeed>& seeds, const std::vector<int32_t>& seed_label,
                         std::vector<double>& d, std::vector<int32_t>& label) {
  const int32_t n = m.num_vertices();
  d.assign(static_cast<size_t>(n), kInf);
  label.assign(static_cast<size_t>(n), -1);
  for (size_t k = 0; k < seeds.size(); ++k)
    if (seeds[k].distance < d[seeds[k].vertex]) {
      d[seeds[k].vertex] = seeds[k].distance;
      label[seeds[k].vertex] = seed_label[k];
    }
  const auto nb = neighbor_sets(m);
  for (bool changed = true; changed;) {
    changed = false;
    for (int32_t i = 0; i < n; ++i)
      for (int32_t j : nb[i])
        if (d[i] + edge(m, i, j) < d[j]) {
          d[j] = d[i] + edge(m, i, j);
          label[j] = label[i];
          changed = true;
        }
  }
}

}  // namespace

TEST_CASE("label_nearest_seeds: the labels of multi-source shortest paths (Bellman-Ford oracle)") {
  const Mesh m = make_random_sphere(500, 11);
  const PatchGrower g = prepare_patch_grower(m);
  GrowWorkspace ws;
  // Three sites as the CVT seeds them: a corner triple at small distances, a
  // lone vertex, and a pair; labels need not be the seed indices.
  const std::vector<GrowSeed> seeds = {{3, 0.01}, {40, 0.02}, {41, 0.005}, {250, 0.0}, {477, 0.03}, {100, 0.0}};
  const std::vector<int32_t> seed_label = {7, 7, 7, 2, 5, 5};
  std::vector<double> d;
  std::vector<int32_t> want;
  oracle_bellman_ford(m, seeds, seed_label, d, want);
  std::vector<int32_t> got(static_cast<size_t>(m.num_vertices()), 99);
  label_nearest_seeds(g.adjacency, g.edge_length, seeds, seed_label, ws, got);
  CHECK(got == want);
  CHECK(std::count(got.begin(), got.end(), 7) > 0);
  CHECK(std::count(got.begin(), got.end(), 2) > 0);
  CHECK(std::count(got.begin(), got.end(), 5) > 0);
  // The workspace is clean afterwards: a plain grow from it gives the oracle's order.
  std::vector<int32_t> order;
  oracle_dijkstra(m, {{9, 0.0}}, order);
  CHECK(grow(g, {{9, 0.0}}, geodesic_disk(500), ws) == order);
  // A vertex reached by two seeds of equal distance keeps the first seed's label.
  std::vector<int32_t> tie(static_cast<size_t>(m.num_vertices()));
  label_nearest_seeds(g.adjacency, g.edge_length, std::vector<GrowSeed>{{8, 0.0}, {8, 0.0}}, std::vector<int32_t>{1, 2},
                      ws, tie);
  CHECK(std::all_of(tie.begin(), tie.end(), [](int32_t l) { return l == 1; }));
}

TEST_CASE("geodesic grows and seed labels on a mesh's positions: the oracles' order and labels") {
  // Edge lengths computed as the grow reaches them, instead of an array per
  // adjacency entry: the same Dijkstra and Bellman-Ford oracles as above.
  const Mesh m = make_random_sphere(500, 11);
  const Adjacency adj = vertex_adjacency(m);
  GrowWorkspace ws;
  // Distinct seed distances: the oracle's order of ties is not the heap's.
  const std::vector<GrowSeed> seeds = {{3, 0.01}, {40, 0.02}, {41, 0.005}, {250, 0.0}, {477, 0.03}, {100, 0.015}};
  std::vector<int32_t> order;
  const std::vector<double> d = oracle_dijkstra(m, seeds, order);
  HostVector<int32_t> got;
  GrowOptions o;
  o.mode = GrowMode::Geodesic;
  grow_geodesic_vertices(adj, m, seeds, o, ws, got);
  CHECK(std::vector<int32_t>(got) == order);
  std::vector<int32_t> from_array;  // and the order of the lengths' array, settle for settle
  grow_vertices(adj, adjacency_edge_lengths(m, adj), seeds, o, ws, from_array);
  CHECK(std::vector<int32_t>(got) == from_array);
  o.max_radius = 0.25;
  o.radius_rule = RadiusRule::PruneBeyond;
  grow_geodesic_vertices(adj, m, seeds, o, ws, got);
  std::vector<int32_t> within;
  for (int32_t v : order)
    if (d[v] <= 0.25) within.push_back(v);
  std::vector<int32_t> sorted(got.begin(), got.end());
  std::sort(sorted.begin(), sorted.end());
  std::sort(within.begin(), within.end());
  CHECK(sorted == within);
  const std::vector<int32_t> seed_label = {7, 7, 7, 2, 5, 5};
  std::vector<double> dist;
  std::vector<int32_t> want;
  oracle_bellman_ford(m, seeds, seed_label, dist, want);
  std::vector<int32_t> label(static_cast<size_t>(m.num_vertices()), 99);
  label_nearest_seeds_by_positions(adj, m, seeds, seed_label, ws, label);
  CHECK(label == want);
  const Mesh other = make_random_sphere(60, 2);
  CHECK_THROWS_AS(label_nearest_seeds_by_positions(adj, other, seeds, seed_label, ws, label), Error);
  CHECK_THROWS_AS(grow_geodesic_vertices(adj, other, seeds, o, ws, got), Error);
}

TEST_CASE("label_nearest_seeds: unreached components get -1; no seeds; usage errors") {
  Mesh m = make_random_sphere(60, 2);
  const int32_t n0 = m.num_vertices();
  // A second, disjoint triangle.
  for (int k = 0; k < 3; ++k) {
    m.x.push_back(5.0 + k);
    m.y.push_back(k == 2 ? 1.0 : 0.0);
    m.z.push_back(0.0);
  }
  m.add_triangle(n0, n0 + 1, n0 + 2);
  const Adjacency adj = vertex_adjacency(m);
  const HostVector<double> len = adjacency_edge_lengths(m, adj);
  GrowWorkspace ws;
  std::vector<int32_t> label(static_cast<size_t>(m.num_vertices()));
  label_nearest_seeds(adj, len, std::vector<GrowSeed>{{0, 0.0}}, std::vector<int32_t>{4}, ws, label);
  for (int32_t v = 0; v < n0; ++v) CHECK(label[v] == 4);
  for (int32_t v = n0; v < n0 + 3; ++v) CHECK(label[v] == -1);
  label_nearest_seeds(adj, len, std::vector<GrowSeed>{}, std::vector<int32_t>{}, ws, label);
  CHECK(std::all_of(label.begin(), label.end(), [](int32_t l) { return l == -1; }));
  CHECK_THROWS_AS(label_nearest_seeds(adj, len, std::vector<GrowSeed>{{n0 + 3, 0.0}}, std::vector<int32_t>{0}, ws, label),
                  Error);
  CHECK_THROWS_AS(label_nearest_seeds(adj, len, std::vector<GrowSeed>{{0, 0.0}}, std::vector<int32_t>{}, ws, label),
                  Error);
  CHECK_THROWS_AS(label_nearest_seeds(adj, {}, std::vector<GrowSeed>{{0, 0.0}}, std::vector<int32_t>{0}, ws, label),
                  Error);
  std::vector<int32_t> short_label(3);
  CHECK_THROWS_AS(
      label_nearest_seeds(adj, len, std::vector<GrowSeed>{{0, 0.0}}, std::vector<int32_t>{0}, ws, short_label), Error);
}
