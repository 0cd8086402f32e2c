// A triangle mesh's corners set aside and rebuilt (engine/src/face_corner_loan.hpp)
// and the cvt command on an exclusive Session, which lends them out while it
// factors and Lloyd runs. Oracles: a copy of the corners taken before, each
// vertex's neighbors as a std::set from the faces, and the same command on a
// Session that lends nothing.
#include <doctest/doctest.h>

#include <map>
#include <set>
#include <vector>

#include "engine/src/face_corner_loan.hpp"
#include "engine/src/incidence_loan.hpp"
#include "tests/engine/lending_sessions.hpp"
#include "tests/engine/neighbor_sets.hpp"
#include "locus/engine/cvt_request.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/pipelines/voronoi/remesh_quality.hpp"
#include "locus/session.hpp"

using namespace locus;

TEST_CASE("face corner loan: a triangle mesh's corners released empty, restored as they were") {
  Mesh m = make_random_sphere(500, 4);
  const HostVector<int32_t> corners = m.face_vertices;
  {
    FaceCornerLoan loan(m);
    loan.release();
    CHECK(loan.released());
    CHECK(m.face_vertices.empty());
    CHECK(m.f0.size() == static_cast<size_t>(m.num_faces()));  // the faces stay in f0/f1/f2
    loan.release();  // twice: still out
    loan.restore();
    CHECK(!loan.released());
    CHECK(m.face_vertices == corners);
    loan.restore();  // not released: nothing
    CHECK(m.face_vertices == corners);
    loan.release();
  }  // released at the end of its scope: restored there (an error's unwinding)
  CHECK(m.face_vertices == corners);
}

TEST_CASE("face corner loan: a polygon mesh keeps its corners (no triangle arrays to read them from)") {
  Mesh m = make_quad_torus(6, 5);
  REQUIRE(!m.is_triangle_mesh());
  const HostVector<int32_t> corners = m.face_vertices;
  FaceCornerLoan loan(m);
  loan.release();
  CHECK(!loan.released());
  CHECK(m.face_vertices == corners);
}

TEST_CASE("incidence loan: the adjacency rebuilt while the corners are out equals each vertex's neighbors") {
  Mesh m = make_random_sphere(600, 3);
  m.add_triangle(3, 3, 7);  // a repeated corner: no self loop
  const std::vector<std::set<int32_t>> want = test::neighbor_sets(m);
  MeshDerived d = derive_mesh(m);
  drop_edge_corners(d.incidence);
  const HostVector<int32_t> corner_edge = d.incidence.corner_edge;
  IncidenceLoan loan(m, d);
  FaceCornerLoan corners(m);  // after `loan`: back before it rebuilds the incidence
  loan.release();
  loan.release_adjacency();
  corners.release();
  REQUIRE(m.face_vertices.empty());
  loan.restore_adjacency();
  test::check_rows(d.adjacency, want);
  corners.restore();
  loan.restore();
  CHECK(d.incidence.corner_edge == corner_edge);
}

TEST_CASE("incidence loan: the incidence rebuilt while the corners are out equals each corner's edge by brute force") {
  Mesh m = make_random_sphere(600, 5);
  m.add_triangle(3, 3, 7);  // a repeated corner: no edge (-1)
  // Oracle: the distinct {smaller, larger} ends of the faces' consecutive
  // corners, ascending; each corner's edge found among them; faces per edge counted.
  std::map<std::pair<int32_t, int32_t>, int32_t> edge_of;
  for (int32_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = m.face(f)[k], b = m.face(f)[(k + 1) % 3];
      if (a != b) edge_of[{std::min(a, b), std::max(a, b)}] = 0;
    }
  int32_t next = 0;
  for (auto& [ends, id] : edge_of) id = next++;
  std::vector<int32_t> want_corner, want_count(edge_of.size(), 0);
  for (int32_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = m.face(f)[k], b = m.face(f)[(k + 1) % 3];
      want_corner.push_back(a == b ? -1 : edge_of.at({std::min(a, b), std::max(a, b)}));
      if (a != b) ++want_count[want_corner.back()];
    }
  const HostVector<int32_t> corners_before = m.face_vertices;
  MeshDerived d = derive_mesh(m);
  drop_edge_corners(d.incidence);
  IncidenceLoan loan(m, d);
  FaceCornerLoan corners(m);
  loan.release();
  loan.release_adjacency();
  corners.release();
  REQUIRE(m.face_vertices.empty());
  CHECK(!loan.restore_reads_corners());  // the CSR was dropped: rebuilt from the adjacency and f0/f1/f2
  loan.restore();                        // the corners still out (the remesh's dual and repair)
  REQUIRE(m.face_vertices.empty());
  const Edges& e = d.incidence.edges;
  REQUIRE(e.e0.size() == edge_of.size());
  for (const auto& [ends, id] : edge_of) {
    CHECK(e.e0[id] == ends.first);
    CHECK(e.e1[id] == ends.second);
    CHECK(e.face_count[id] == want_count[id]);
  }
  CHECK(std::vector<int32_t>(d.incidence.corner_edge.begin(), d.incidence.corner_edge.end()) == want_corner);
  corners.restore();
  CHECK(m.face_vertices == corners_before);
}

TEST_CASE("cvt on an exclusive Session with corners lent: the same remesh, refined or not, the mesh whole after") {
  const Mesh m = make_random_sphere(3000, 7);
  // 120 sites: no refinement; 300: 3000 < 12 x 300 vertices, so the remesh
  // subdivides the input (which reads its corners) before Lloyd.
  for (int32_t sites : {120, 300}) {
    CAPTURE(sites);
    CvtRequest q;
    q.sites = sites;
    q.iters = 3;
    const test::LendingSessions sessions(m);
    const Session &shared = sessions.shared, &lent = sessions.lent;
    const CvtReport a = shared.cvt(q), b = lent.cvt(q);
    CHECK(a.complete == b.complete);
    CHECK(a.refinements == b.refinements);
    if (sites == 300) CHECK(a.refinements > 0);
    CHECK(a.site_xyz == b.site_xyz);
    CHECK(a.label == b.label);
    CHECK(a.remesh.x == b.remesh.x);
    CHECK(a.remesh.face_vertices == b.remesh.face_vertices);
    CHECK(lent.mesh().face_vertices == m.face_vertices);
  }
}

TEST_CASE("cvt on an exclusive Session with corners lent, on a disk: the repair reads its boundary loops meanwhile") {
  // The restricted dual's topology walks the boundary loops before the corners
  // come back (through f0/f1/f2, boundary_loops).
  const Mesh m = make_disk(20, 0.3, 5);  // 1,261 vertices: no refinement at 80 sites
  CvtRequest q;
  q.sites = 80;
  q.iters = 3;
  const test::LendingSessions sessions(m);
  const Session &shared = sessions.shared, &lent = sessions.lent;
  const CvtReport a = shared.cvt(q), b = lent.cvt(q);
  REQUIRE(a.complete);
  CHECK(b.complete);
  CHECK(a.refinements == 0);
  CHECK(a.remesh_stats.boundary_loops == 1);
  // The input's figures from the Session's check: a fresh analysis's.
  const RemeshStats fresh = mesh_topology_stats(m);
  for (const CvtReport* r : {&a, &b}) {
    CHECK(r->input_stats.genus == fresh.genus);
    CHECK(r->input_stats.components == fresh.components);
    CHECK(r->input_stats.boundary_loops == fresh.boundary_loops);
    CHECK(r->input_stats.manifold == fresh.manifold);
  }
  CHECK(a.remesh.x == b.remesh.x);
  CHECK(a.remesh.face_vertices == b.remesh.face_vertices);
  CHECK(lent.mesh().face_vertices == m.face_vertices);
}
