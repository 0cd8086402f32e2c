// The edge incidence and the vertex adjacency set aside and rebuilt
// (engine/src/incidence_loan.hpp) and the cvt command on an exclusive Session,
// which lends them out while it factors and Lloyd runs. Oracles: the incidence
// rebuilt by brute force from the faces (std::map of the sorted corner pairs:
// edges, face counts, each corner's edge, each edge's corners), each vertex's
// neighbors as a std::set from the faces, and the same command on a Session
// that lends nothing.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "engine/src/incidence_loan.hpp"
#include "tests/engine/lending_sessions.hpp"
#include "tests/engine/neighbor_sets.hpp"
#include "locus/engine/cvt_request.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/session.hpp"

using namespace locus;

namespace {

// d.incidence against the faces: every field, the edge-to-corner CSR present or not.
void check_incidence(const Mesh& m, const EdgeIncidence& inc, bool with_corners) {
  std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> corners;  // edge -> its corners, ascending
  for (int32_t c = 0; c < static_cast<int32_t>(m.face_vertices.size()); ++c) {
    const int32_t f = static_cast<int32_t>(
        std::upper_bound(m.face_offsets.begin(), m.face_offsets.end(), c) - m.face_offsets.begin() - 1);
    const int32_t next = c + 1 < m.face_offsets[f + 1] ? c + 1 : m.face_offsets[f];
    const int32_t a = m.face_vertices[c], b = m.face_vertices[next];
    corners[{std::min(a, b), std::max(a, b)}].push_back(c);
  }
  REQUIRE(inc.edges.e0.size() == corners.size());
  REQUIRE(inc.edges.e1.size() == corners.size());
  REQUIRE(inc.edges.face_count.size() == corners.size());
  REQUIRE(inc.corner_edge.size() == m.face_vertices.size());
  int32_t e = 0;
  for (const auto& [edge, list] : corners) {
    CHECK(inc.edges.e0[e] == edge.first);
    CHECK(inc.edges.e1[e] == edge.second);
    CHECK(inc.edges.face_count[e] == static_cast<int32_t>(list.size()));
    for (int32_t c : list) CHECK(inc.corner_edge[c] == e);
    if (with_corners) {
      REQUIRE(inc.edge_corner_offsets.size() == corners.size() + 1);
      CHECK(std::vector<int32_t>(inc.edge_corners.begin() + inc.edge_corner_offsets[e],
                                 inc.edge_corners.begin() + inc.edge_corner_offsets[e + 1]) == list);
    }
    ++e;
  }
  if (!with_corners) {
    CHECK(inc.edge_corner_offsets.empty());
    CHECK(inc.edge_corners.empty());
  }
}

}  // namespace

TEST_CASE("incidence loan: released empty, restored equal to the faces' incidence, with or without its CSR") {
  const Mesh m = make_random_sphere(600, 3);
  for (bool with_corners : {true, false}) {
    CAPTURE(with_corners);
    MeshDerived d = derive_mesh(m);
    if (!with_corners) drop_edge_corners(d.incidence);
    check_incidence(m, d.incidence, with_corners);
    const HostVector<int32_t> adjacency = d.adjacency.neighbors;
    {
      IncidenceLoan loan(m, d);
      loan.release();
      CHECK(loan.released());
      CHECK(d.incidence.edges.e0.empty());
      CHECK(d.incidence.corner_edge.empty());
      CHECK(d.incidence.edge_corners.empty());
      loan.release();  // twice: still out, nothing else happens
      loan.restore();
      CHECK(!loan.released());
      check_incidence(m, d.incidence, with_corners);
      loan.restore();  // not released: nothing
      check_incidence(m, d.incidence, with_corners);
      loan.release();
    }  // released at the end of its scope: restored there (an error's unwinding)
    check_incidence(m, d.incidence, with_corners);
    CHECK(d.adjacency.neighbors == adjacency);  // nothing else of d is touched
  }
}

TEST_CASE("incidence loan: the adjacency released and rebuilt from the faces equals each vertex's neighbors") {
  // A closed surface, a grid (boundary, quads split by its generator), a quad
  // torus (polygon faces) and a sphere with a degenerate triangle (a repeated
  // corner: no self loop) and a repeated face (each neighbor once).
  Mesh degenerate = make_random_sphere(400, 5);
  degenerate.add_triangle(3, 3, 7);
  degenerate.add_triangle(degenerate.f0[0], degenerate.f1[0], degenerate.f2[0]);
  for (const Mesh& m : {make_random_sphere(600, 3), make_grid(9), make_quad_torus(6, 5), degenerate}) {
    const std::vector<std::set<int32_t>> want = test::neighbor_sets(m);  // the oracle
    MeshDerived d = derive_mesh(m);
    drop_edge_corners(d.incidence);  // restore() then rebuilds the incidence from the adjacency
    const HostVector<int32_t> corner_edge = d.incidence.corner_edge;
    IncidenceLoan loan(m, d);
    loan.release();
    loan.release_adjacency();
    CHECK(d.adjacency.offsets.empty());
    CHECK(d.adjacency.neighbors.empty());
    loan.restore_adjacency();
    test::check_rows(d.adjacency, want);
    CHECK(d.adjacency.neighbors.size() == static_cast<size_t>(d.adjacency.offsets.back()));
    loan.release_adjacency();
    loan.restore();  // the incidence from the rebuilt adjacency, the adjacency first
    CHECK(!d.adjacency.neighbors.empty());
    CHECK(d.incidence.corner_edge == corner_edge);
  }
}

TEST_CASE("cvt on an exclusive Session: the same remesh as on a shared one, the Session whole after it") {
  const Mesh m = make_random_sphere(3000, 7);
  CvtRequest q;
  q.sites = 120;
  q.iters = 4;
  const test::LendingSessions sessions(m);
  const Session &shared = sessions.shared, &lent = sessions.lent;
  const CvtReport a = shared.cvt(q), b = lent.cvt(q);
  REQUIRE(a.complete);
  REQUIRE(b.complete);
  CHECK(a.site_xyz == b.site_xyz);
  CHECK(a.label == b.label);
  CHECK(a.remesh.x == b.remesh.x);
  CHECK(a.remesh.face_vertices == b.remesh.face_vertices);
  // Its incidence back: a second remesh (its dual reads it) and the mesh's
  // topology (its edges) are what they were.
  const CvtReport again = lent.cvt(q);
  CHECK(again.remesh.face_vertices == b.remesh.face_vertices);
  CHECK(lent.info().n_edges == shared.info().n_edges);
}
