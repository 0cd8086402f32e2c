// Tests for kernels/mesh_topology.{hpp,cpp} and mesh_topology_report.cpp.
// Oracles: closed-form counts (icosahedron V=10*4^l+2, E=30*4^l, F=20*4^l; Euler's
// formula for sphere, torus, disc), brute-force std::set constructions of edges and
// neighbors, and hand-built broken meshes whose defect is known by construction.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"

using namespace locus;

namespace {

Mesh tri_mesh(std::vector<std::array<double, 3>> pts, std::vector<std::array<int32_t, 3>> tris) {
  Mesh m;
  for (auto& p : pts) m.add_vertex(p[0], p[1], p[2]);
  for (auto& t : tris) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

// Appends b to a with shifted indices.
Mesh concat(const Mesh& a, const Mesh& b) {
  Mesh m = a;
  const int32_t shift = a.num_vertices();
  for (int32_t v = 0; v < b.num_vertices(); ++v) m.add_vertex(b.x[v] + 3.0, b.y[v], b.z[v]);
  for (int32_t f = 0; f < b.num_faces(); ++f) {
    std::vector<int32_t> vs(b.face(f).begin(), b.face(f).end());
    for (auto& v : vs) v += shift;
    m.add_face(vs);
  }
  return m;
}

std::string message_of(const Mesh& m, const MeshRequirements& req) {
  try {
    check_requirements(m, req);
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadInput);
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("icosphere counts, Euler characteristic and genus match the closed-form values") {
  for (int level = 0; level <= 4; ++level) {
    const Mesh m = make_icosphere(level);
    const MeshReport r = analyze_mesh(m);
    const int64_t p = int64_t(1) << (2 * level);
    CHECK(r.n_vertices == 10 * p + 2);
    CHECK(r.n_edges == 30 * p);
    CHECK(r.n_faces == 20 * p);
    CHECK(r.euler_characteristic == 2);
    CHECK(r.genus == 0);
    CHECK(r.boundary_loops == 0);
    CHECK(r.boundary_edges == 0);
    CHECK(r.components == 1);
    CHECK(r.manifold);
    CHECK(r.non_manifold_edges == 0);
    CHECK(r.non_manifold_vertices == 0);
    CHECK(r.degenerate_faces == 0);
    CHECK(r.unreferenced_vertices == 0);
    REQUIRE(r.face_degree_histogram.size() == 4);
    CHECK(r.face_degree_histogram[3] == r.n_faces);
    CHECK(r.bbox_max[0] <= 1.0 + 1e-12);
    CHECK(r.bbox_min[2] >= -1.0 - 1e-12);
    CHECK_NOTHROW(check_requirements(m, MeshRequirements{.connected = true, .closed = true}));
  }
}

TEST_CASE("torus and quad torus have chi 0 and genus 1") {
  const MeshReport t = analyze_mesh(make_torus(12, 7));
  CHECK(t.n_vertices == 84);
  CHECK(t.n_faces == 168);
  CHECK(t.n_edges == 3 * 84);
  CHECK(t.euler_characteristic == 0);
  CHECK(t.genus == 1);
  CHECK(t.manifold);
  CHECK(t.boundary_loops == 0);
  const Mesh q = make_quad_torus(9, 5);
  const MeshReport r = analyze_mesh(q);
  CHECK(r.n_faces == 45);
  CHECK(r.n_edges == 90);
  REQUIRE(r.face_degree_histogram.size() == 5);
  CHECK(r.face_degree_histogram[4] == 45);
  CHECK(r.face_degree_histogram[3] == 0);
  CHECK(r.euler_characteristic == 0);
  CHECK(r.genus == 1);
  CHECK(r.manifold);
  CHECK(r.first_non_triangle_face == 0);
  CHECK(message_of(q, {}) == "mesh: face 0 has 4 vertices; this pipeline needs triangles");
  CHECK_NOTHROW(check_requirements(q, MeshRequirements{.triangles = false, .connected = true, .closed = true}));
}

TEST_CASE("disk and grid: one counter-clockwise boundary loop, chi 1, genus 0") {
  for (double flips : {0.0, 0.5}) {
    const Mesh d = make_disk(6, flips, 3);
    const MeshReport r = analyze_mesh(d);
    CHECK(r.boundary_loops == 1);
    CHECK(r.euler_characteristic == 1);
    CHECK(r.genus == 0);
    CHECK(r.manifold);
    const auto loops = boundary_loops(d);
    REQUIRE(loops.size() == 1);
    REQUIRE(loops[0].size() == 36);
    // The same loops from the triangle arrays alone (face_vertices lent out).
    const EdgeIncidence inc = edge_incidence(d);
    Mesh lent = d;
    lent.face_vertices = HostVector<int32_t>{};
    CHECK(boundary_loops(lent, inc) == loops);
    // The outer ring: every loop vertex at radius 1, signed area of the loop polygon
    // positive (counter-clockwise) and equal to that of the regular 36-gon.
    double area2 = 0;
    for (size_t k = 0; k < loops[0].size(); ++k) {
      const int32_t a = loops[0][k], b = loops[0][(k + 1) % loops[0].size()];
      CHECK(std::hypot(d.x[a], d.y[a]) == doctest::Approx(1.0).epsilon(1e-12));
      area2 += d.x[a] * d.y[b] - d.x[b] * d.y[a];
    }
    CHECK(0.5 * area2 == doctest::Approx(18.0 * std::sin(2 * M_PI / 36)).epsilon(1e-12));
  }
  const Mesh g = make_grid(5, 0.3, 9);
  const MeshReport r = analyze_mesh(g);
  CHECK(r.n_vertices == 36);
  CHECK(r.n_faces == 50);
  CHECK(r.euler_characteristic == 1);
  CHECK(r.boundary_loops == 1);
  CHECK(r.boundary_edges == 20);
  CHECK(boundary_loops(g)[0].size() == 20);
  CHECK(message_of(g, MeshRequirements{.closed = true}) ==
        "mesh: mesh has 1 boundary loop (one through vertex " + std::to_string(r.first_boundary_vertex) +
            "); this pipeline needs a closed mesh");
}

TEST_CASE("annulus: two boundary loops, genus 0") {
  // Quad strip around a square hole: 8 outer + 8 inner vertices, chi = 0, b = 2.
  Mesh m;
  const double o[8][2] = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
  for (auto& p : o) m.add_vertex(p[0], p[1], 0);
  for (auto& p : o) m.add_vertex(0.5 + 0.5 * p[0], 0.5 + 0.5 * p[1], 0);
  for (int32_t i = 0; i < 8; ++i) {
    const int32_t j = (i + 1) % 8;
    m.add_triangle(i, j, 8 + j);
    m.add_triangle(i, 8 + j, 8 + i);
  }
  const MeshReport r = analyze_mesh(m);
  CHECK(r.euler_characteristic == 0);
  CHECK(r.boundary_loops == 2);
  CHECK(r.genus == 0);
  const auto loops = boundary_loops(m);
  REQUIRE(loops.size() == 2);
  CHECK(loops[0].size() == 8);
  CHECK(loops[1].size() == 8);
  // Outer loop runs counter-clockwise (0 -> 1), the hole clockwise (surface on the left).
  CHECK(loops[0][0] == 0);
  CHECK(loops[0][1] == 1);
  CHECK(loops[1][0] == 9);
  CHECK(loops[1][1] == 8);
  CHECK(loops[1][2] == 15);
}

TEST_CASE("unique edges and adjacency equal brute-force sets") {
  for (const Mesh& m : {make_grid(7, 0.5, 4), make_icosphere(2), make_disk(4, 1.0, 2), make_quad_torus(5, 4)}) {
    std::map<std::pair<int32_t, int32_t>, int32_t> ref;
    std::vector<std::set<int32_t>> nbr(m.num_vertices());
    for (int32_t f = 0; f < m.num_faces(); ++f) {
      const auto fv = m.face(f);
      for (size_t k = 0; k < fv.size(); ++k) {
        const int32_t a = fv[k], b = fv[(k + 1) % fv.size()];
        ++ref[{std::min(a, b), std::max(a, b)}];
        nbr[a].insert(b);
        nbr[b].insert(a);
      }
    }
    const Edges e = unique_edges(m);
    REQUIRE(e.e0.size() == ref.size());
    size_t k = 0;
    for (const auto& [edge, count] : ref) {  // std::map iterates lexicographically
      CHECK(e.e0[k] == edge.first);
      CHECK(e.e1[k] == edge.second);
      CHECK(e.face_count[k] == count);
      ++k;
    }
    const Adjacency adj = vertex_adjacency(m);
    REQUIRE(adj.offsets.size() == size_t(m.num_vertices()) + 1);
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
      const std::vector<int32_t> got(adj.neighbors.begin() + adj.offsets[v], adj.neighbors.begin() + adj.offsets[v + 1]);
      CHECK(got == std::vector<int32_t>(nbr[v].begin(), nbr[v].end()));
    }
    const double h = mean_edge_length(m);
    double sum = 0;
    for (const auto& [edge, count] : ref)
      sum += std::sqrt(std::pow(m.x[edge.first] - m.x[edge.second], 2) + std::pow(m.y[edge.first] - m.y[edge.second], 2) +
                       std::pow(m.z[edge.first] - m.z[edge.second], 2));
    CHECK(h == doctest::Approx(sum / ref.size()).epsilon(1e-12));
  }
}

TEST_CASE("connected components over referenced vertices") {
  Mesh m = concat(make_icosphere(1), make_torus(6, 4));
  m.add_vertex(9, 9, 9);  // unreferenced
  std::vector<int32_t> comp;
  CHECK(connected_components(m, comp) == 2);
  for (int32_t v = 0; v < 42; ++v) CHECK(comp[v] == 0);
  for (int32_t v = 42; v < 66; ++v) CHECK(comp[v] == 1);
  CHECK(comp[66] == -1);
  const MeshReport r = analyze_mesh(m);
  CHECK(r.components == 2);
  CHECK(r.genus == -1);
  CHECK(r.unreferenced_vertices == 1);
  CHECK(r.first_unreferenced_vertex == 66);
  CHECK(r.euler_characteristic == 2 + 0);
  m.source = "two.off";
  CHECK(message_of(m, {}) == "two.off: vertex 66 is not referenced by any face");
  CHECK(message_of(m, MeshRequirements{.no_unreferenced_vertices = false, .connected = true}) ==
        "two.off: mesh has 2 connected components; this pipeline needs a connected mesh");
}

TEST_CASE("non-manifold edge shared by three faces") {
  Mesh m = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  m.source = "fin.off";
  const MeshReport r = analyze_mesh(m);
  CHECK_FALSE(r.manifold);
  CHECK(r.non_manifold_edges == 1);
  CHECK(r.first_non_manifold_edge_v0 == 0);
  CHECK(r.first_non_manifold_edge_v1 == 1);
  CHECK(r.genus == -1);
  CHECK(message_of(m, {}) == "fin.off: edge (0, 1) is shared by 3 faces (non-manifold)");
  CHECK_NOTHROW(check_requirements(m, MeshRequirements{.manifold = false}));
}

TEST_CASE("inconsistent orientation is a non-manifold edge") {
  Mesh m = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}}, {{0, 1, 2}, {0, 1, 3}});
  m.source = "flip.off";
  const MeshReport r = analyze_mesh(m);
  CHECK(r.non_manifold_edges == 1);
  CHECK(r.non_manifold_vertices == 0);
  CHECK_FALSE(r.manifold);
  CHECK(message_of(m, {}) == "flip.off: edge (0, 1) is traversed in the same direction by faces 0 and 1 "
                             "(inconsistent orientation)");
  // Orient face 1 consistently and the mesh is a manifold disc.
  Mesh ok = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}}, {{0, 1, 2}, {1, 0, 3}});
  CHECK(analyze_mesh(ok).manifold);
  CHECK(analyze_mesh(ok).genus == 0);
}

TEST_CASE("bowtie vertex: two fans meeting at one vertex") {
  Mesh m = tri_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}, {{0, 1, 2}, {0, 3, 4}});
  m.source = "bowtie.off";
  const MeshReport r = analyze_mesh(m);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.non_manifold_vertices == 1);
  CHECK(r.first_non_manifold_vertex == 0);
  CHECK_FALSE(r.manifold);
  CHECK(r.components == 1);
  CHECK(message_of(m, {}) == "bowtie.off: vertex 0 is non-manifold (its faces form 2 separate fans)");
  // A closed fan (pyramid without base) around the vertex is one fan.
  Mesh fan = tri_mesh({{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}}, {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}});
  CHECK(analyze_mesh(fan).non_manifold_vertices == 0);
  CHECK(analyze_mesh(fan).boundary_loops == 1);
}

TEST_CASE("zero-area triangle is reported and rejected") {
  Mesh m = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}}, {{0, 1, 2}, {0, 3, 1}});
  m.source = "x.off";
  const MeshReport r = analyze_mesh(m);
  CHECK(r.degenerate_faces == 1);
  CHECK(r.first_degenerate_face == 1);
  CHECK(message_of(m, {}) == "x.off: face 1 has zero area");
  // A tiny but valid triangle (area 1e-10 * h^2) is not degenerate.
  Mesh tiny = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1e-10, 0}}, {{0, 1, 2}});
  CHECK(analyze_mesh(tiny).degenerate_faces == 0);
}

TEST_CASE("non-finite coordinates are reported before anything they would poison") {
  Mesh m = make_icosphere(1);
  m.z[9] = std::numeric_limits<double>::infinity();
  m.x[20] = std::nan("");
  m.source = "inf.off";
  const MeshReport r = analyze_mesh(m);
  CHECK(r.non_finite_vertices == 2);
  CHECK(r.first_non_finite_vertex == 9);
  CHECK(message_of(m, {}) == "inf.off: vertex 9 has a non-finite coordinate");
}

TEST_CASE("hostile arrays are rejected with BadInput, never read out of bounds") {
  Mesh m = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  m.face_vertices[2] = 99;
  m.f2.clear();
  m.f0.clear();
  m.f1.clear();
  m.source = "bad.off";
  CHECK_THROWS_WITH_AS(analyze_mesh(m), "bad.off: face 0 references vertex 99 but the mesh has 3 vertices", Error);
  m.face_vertices[2] = -1;
  CHECK_THROWS_AS(unique_edges(m), Error);
  Mesh two = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {});
  two.face_vertices = {0, 1};
  two.face_offsets = {0, 2};
  CHECK_THROWS_WITH_AS(analyze_mesh(two), "mesh: face 0 has 2 vertices; a face needs at least 3", Error);
  Mesh ragged = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  ragged.y.pop_back();
  CHECK_THROWS_AS(vertex_adjacency(ragged), Error);
  Mesh offs = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  offs.face_offsets = {0, 5};
  CHECK_THROWS_AS(boundary_loops(offs), Error);
  std::vector<int32_t> comp;
  CHECK_THROWS_AS(connected_components(offs, comp), Error);
  Mesh empty;
  const MeshReport r = analyze_mesh(empty);
  CHECK(r.n_vertices == 0);
  CHECK(r.components == 0);
  CHECK(r.genus == -1);
}

TEST_CASE("armadillo.off: one closed genus-0 component") {
  const std::string path = std::string(LOCUS_MESH_CACHE_DIR) + "/armadillo.off";
  if (!std::filesystem::exists(path)) {
    MESSAGE("skipped: " << path << " is missing (tools/fetch_meshes.sh)");
    return;
  }
  const Mesh m = read_mesh(path);
  const MeshReport r = analyze_mesh(m);
  CHECK(r.n_vertices == 26002);
  CHECK(r.n_faces == 52000);
  CHECK(r.n_edges == 78000);
  CHECK(r.components == 1);
  CHECK(r.boundary_loops == 0);
  CHECK(r.euler_characteristic == 2);
  CHECK(r.genus == 0);
  CHECK(r.manifold);
  CHECK_NOTHROW(check_requirements(m, MeshRequirements{.connected = true, .closed = true}));
}

TEST_CASE("random polygon soups: analysis never fails on valid indices and its counts add up") {
  // Faces of degree 3..6 over a few vertices, repeated vertices allowed: every kind of
  // defect at once. Oracles: brute-force counts of half-edges, referenced vertices and
  // degrees; the Euler characteristic from its definition.
  std::mt19937_64 rng(12345);
  for (int trial = 0; trial < 300; ++trial) {
    Mesh m;
    const int32_t nv = 1 + static_cast<int32_t>(rng() % 12);
    for (int32_t v = 0; v < nv; ++v) m.add_vertex(double(rng() % 5), double(rng() % 5), double(rng() % 3));
    const int32_t nf = static_cast<int32_t>(rng() % 15);
    int64_t proper_half_edges = 0;
    std::set<int32_t> referenced;
    std::vector<int64_t> hist(7, 0);
    for (int32_t f = 0; f < nf; ++f) {
      const int32_t d = 3 + static_cast<int32_t>(rng() % 4);
      std::vector<int32_t> vs(d);
      for (auto& v : vs) v = static_cast<int32_t>(rng() % nv);
      for (int32_t k = 0; k < d; ++k) {
        proper_half_edges += vs[k] != vs[(k + 1) % d];
        referenced.insert(vs[k]);
      }
      ++hist[d];
      m.add_face(vs);
    }
    const MeshReport r = analyze_mesh(m);
    const Edges e = unique_edges(m);
    int64_t sum = 0;
    for (int32_t c : e.face_count) sum += c;
    CHECK(sum == proper_half_edges);
    CHECK(r.unreferenced_vertices == nv - static_cast<int64_t>(referenced.size()));
    CHECK(r.euler_characteristic == static_cast<int64_t>(referenced.size()) - r.n_edges + nf);
    for (size_t d = 0; d < r.face_degree_histogram.size(); ++d) CHECK(r.face_degree_histogram[d] == hist[d]);
    CHECK(r.components <= static_cast<int32_t>(referenced.size()));
    CHECK((r.manifold == (r.non_manifold_edges == 0 && r.non_manifold_vertices == 0)));
    std::vector<int32_t> comp;
    CHECK(connected_components(m, comp) == r.components);
    // Every boundary edge is walked once: a closed loop of L vertices uses L edges, an
    // open chain (next to non-manifold edges) L - 1.
    int64_t boundary_vertices = 0;
    const auto loops = boundary_loops(m);
    for (const auto& loop : loops) boundary_vertices += static_cast<int64_t>(loop.size());
    CHECK(boundary_vertices >= r.boundary_edges);
    CHECK(boundary_vertices <= r.boundary_edges + static_cast<int64_t>(loops.size()));
    CHECK(static_cast<int64_t>(loops.size()) == r.boundary_loops);
    try {
      check_requirements(m, MeshRequirements{.connected = true, .closed = true});
    } catch (const Error& err) {
      CHECK(err.code() == ErrorCode::BadInput);
      CHECK(std::string(err.what()).rfind("mesh: ", 0) == 0);
    }
  }
}

namespace {

// Brute-force manifold report from the definition, with std::map over the
// faces' own half-edges: the non-manifold edges (> 2 faces, or 2 faces running
// it the same way), and per vertex the fans (its corners joined across the
// edges of exactly two faces).
struct BruteManifold {
  int64_t bad_edges = 0, bad_vertices = 0;
  std::pair<int32_t, int32_t> first_edge{-1, -1};
  std::array<int32_t, 3> first_edge_faces{-1, -1, -1};  // face count, first two faces
  int32_t first_vertex = -1, first_vertex_fans = 0;
};

BruteManifold brute_manifold(const Mesh& m) {
  struct Half {
    int32_t face, pos;
    bool up;  // runs from the smaller to the larger end
  };
  std::map<std::pair<int32_t, int32_t>, std::vector<Half>> edges;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto vs = m.face(f);
    const int32_t d = static_cast<int32_t>(vs.size());
    for (int32_t k = 0; k < d; ++k) {
      const int32_t u = vs[k], w = vs[(k + 1) % d];
      if (u != w) edges[{std::min(u, w), std::max(u, w)}].push_back({f, k, u < w});
    }
  }
  BruteManifold b;
  // Corners as (face, position); parent pointers in a map.
  std::map<std::pair<int32_t, int32_t>, std::pair<int32_t, int32_t>> parent;
  const auto find = [&](std::pair<int32_t, int32_t> c) {
    while (parent.at(c) != c) c = parent.at(c);
    return c;
  };
  for (int32_t f = 0; f < m.num_faces(); ++f)
    for (int32_t k = 0; k < static_cast<int32_t>(m.face(f).size()); ++k) parent[{f, k}] = {f, k};
  for (const auto& [key, hs] : edges) {
    const bool bad = hs.size() > 2 || (hs.size() == 2 && hs[0].up == hs[1].up);
    if (bad) {
      if (b.bad_edges++ == 0) {
        b.first_edge = key;
        b.first_edge_faces = {static_cast<int32_t>(hs.size()), hs[0].face, hs[1].face};
      }
    }
    if (hs.size() != 2) continue;
    for (const int32_t v : {key.first, key.second}) {
      std::pair<int32_t, int32_t> at[2];
      for (int i = 0; i < 2; ++i) {
        const auto vs = m.face(hs[i].face);
        const int32_t d = static_cast<int32_t>(vs.size());
        at[i] = {hs[i].face, vs[hs[i].pos] == v ? hs[i].pos : (hs[i].pos + 1) % d};
      }
      const auto ra = find(at[0]), rb = find(at[1]);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
  }
  std::map<int32_t, std::set<std::pair<int32_t, int32_t>>> fans;
  for (int32_t f = 0; f < m.num_faces(); ++f)
    for (int32_t k = 0; k < static_cast<int32_t>(m.face(f).size()); ++k) fans[m.face(f)[k]].insert(find({f, k}));
  for (const auto& [v, roots] : fans)
    if (roots.size() > 1 && b.bad_vertices++ == 0) {
      b.first_vertex = v;
      b.first_vertex_fans = static_cast<int32_t>(roots.size());
    }
  return b;
}

void check_against_brute(const Mesh& m) {
  const MeshReport r = analyze_mesh(m);
  const BruteManifold b = brute_manifold(m);
  CHECK(r.non_manifold_edges == b.bad_edges);
  CHECK(r.non_manifold_vertices == b.bad_vertices);
  CHECK(r.first_non_manifold_vertex == b.first_vertex);
  if (b.first_vertex >= 0) CHECK(r.first_non_manifold_vertex_fans == b.first_vertex_fans);
  CHECK(r.first_non_manifold_edge_v0 == b.first_edge.first);
  CHECK(r.first_non_manifold_edge_v1 == b.first_edge.second);
  if (b.bad_edges > 0) {
    CHECK(r.first_non_manifold_edge_faces == b.first_edge_faces[0]);
    CHECK(r.first_non_manifold_edge_face_a == b.first_edge_faces[1]);
    CHECK(r.first_non_manifold_edge_face_b == b.first_edge_faces[2]);
  }
  CHECK(r.manifold == (b.bad_edges == 0 && b.bad_vertices == 0));
}

}  // namespace

TEST_CASE("manifold checks equal a brute-force count on soups and on damaged spheres") {
  std::mt19937_64 rng(2026);
  // Soups: every defect at once, polygons and repeated vertices included.
  for (int trial = 0; trial < 200; ++trial) {
    Mesh m;
    const int32_t nv = 1 + static_cast<int32_t>(rng() % 10);
    for (int32_t v = 0; v < nv; ++v) m.add_vertex(double(rng() % 5), double(rng() % 5), double(rng() % 3));
    for (int32_t f = 0, nf = static_cast<int32_t>(rng() % 12); f < nf; ++f) {
      std::vector<int32_t> vs(3 + rng() % 3);
      for (auto& v : vs) v = static_cast<int32_t>(rng() % nv);
      m.add_face(vs);
    }
    check_against_brute(m);
  }
  // Icospheres with a few faces removed, duplicated or flipped, or two vertices
  // merged (pinches: several fans at one vertex): sparse defects among many
  // good vertices.
  const Mesh sphere = make_icosphere(2);
  for (int trial = 0; trial < 60; ++trial) {
    Mesh m;
    for (int32_t v = 0; v < sphere.num_vertices(); ++v) m.add_vertex(sphere.x[v], sphere.y[v], sphere.z[v]);
    const int32_t a = static_cast<int32_t>(rng() % sphere.num_vertices());
    const int32_t b = static_cast<int32_t>(rng() % sphere.num_vertices());
    const bool merge = trial % 3 == 0;
    for (int32_t f = 0; f < sphere.num_faces(); ++f) {
      std::vector<int32_t> vs(sphere.face(f).begin(), sphere.face(f).end());
      if (merge)
        for (auto& v : vs) v = v == b ? a : v;
      const uint64_t dice = rng() % 100;
      if (dice < 3) continue;                              // a hole
      if (dice < 5) std::swap(vs[1], vs[2]);               // flipped
      m.add_face(vs);
      if (dice >= 98) m.add_face(vs);                      // a third face on its edges
    }
    check_against_brute(m);
  }
}

TEST_CASE("an incidence without its edge-to-corner lists: EdgeCorners rebuilds them, boundary loops and reports agree") {
  const Mesh fin = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  const Mesh flip = tri_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}}, {{0, 1, 2}, {0, 1, 3}});
  for (const Mesh& m : {make_grid(6, 0.4, 3), make_disk(4, 1.0, 2), make_quad_torus(5, 4), make_icosphere(1), fin, flip}) {
    // Oracle: per edge (lexicographic (lo, hi)), the corners whose half-edge runs along it, ascending.
    std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> ref;
    for (int32_t f = 0; f < m.num_faces(); ++f)
      for (int32_t c = m.face_offsets[f]; c < m.face_offsets[f + 1]; ++c) {
        const int32_t a = m.face_vertices[c], b = m.face_vertices[c + 1 == m.face_offsets[f + 1] ? m.face_offsets[f] : c + 1];
        ref[{std::min(a, b), std::max(a, b)}].push_back(c);
      }
    const EdgeIncidence full = edge_incidence(m);
    EdgeIncidence lean = full;
    drop_edge_corners(lean);
    CHECK(lean.edge_corner_offsets.empty());
    CHECK(lean.edge_corners.empty());
    const EdgeCorners rebuilt(lean), borrowed(full);
    CHECK(borrowed.offsets() == full.edge_corner_offsets.data());  // held: not copied
    REQUIRE(full.edges.e0.size() == ref.size());
    size_t e = 0;
    for (const auto& [edge, corners] : ref) {
      const std::vector<int32_t> got(rebuilt.corners() + rebuilt.offsets()[e], rebuilt.corners() + rebuilt.offsets()[e + 1]);
      CHECK(got == corners);
      CHECK(rebuilt.first(static_cast<int64_t>(e)) == corners.front());
      ++e;
    }
    CHECK(boundary_loops(m, lean) == boundary_loops(m, full));
    const MeshReport a = analyze_mesh(m, full), b = analyze_mesh(m, lean);
    CHECK(a.first_non_manifold_edge_face_a == b.first_non_manifold_edge_face_a);
    CHECK(a.first_non_manifold_edge_face_b == b.first_non_manifold_edge_face_b);
    CHECK(a.boundary_loops == b.boundary_loops);
    CHECK(a.non_manifold_edges == b.non_manifold_edges);
  }
}
