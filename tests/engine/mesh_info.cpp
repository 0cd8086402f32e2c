// The mesh report of every front end (engine/include/locus/engine/mesh_info.hpp):
// Session::info and locus_info_run against analytic counts — an icosphere of
// level k has 10*4^k + 2 vertices, 30*4^k edges and 20*4^k faces (genus 0); a
// torus of nu x nv quads has genus 1 and Euler characteristic 0; an n x n grid
// of quads is a disk with one boundary loop; a planted unreferenced vertex and a
// fin (a third face on an edge) are counted and named.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/engine/mesh_info.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/locus.h"
#include "locus/session.hpp"

using namespace locus;

TEST_CASE("mesh_info: icosphere sizes and topology") {
  for (int k : {0, 2}) {
    const int64_t p = int64_t(1) << (2 * k);
    const Mesh m = make_icosphere(k);
    const MeshInfo i = Session(Mesh(m)).info();
    CHECK(i.n_vertices == 10 * p + 2);
    CHECK(i.n_edges == 30 * p);
    CHECK(i.n_faces == 20 * p);
    REQUIRE(i.face_degree_histogram.size() == 4);
    CHECK(i.face_degree_histogram[3] == 20 * p);
    CHECK(i.euler_characteristic == 2);
    CHECK(i.genus == 0);
    CHECK(i.components == 1);
    CHECK(i.boundary_loops == 0);
    CHECK(i.manifold);
    // The box of the coordinates (an icosahedron's vertices are not at the poles of every axis).
    CHECK(i.bbox_min[0] == *std::min_element(m.x.begin(), m.x.end()));
    CHECK(i.bbox_max[1] == *std::max_element(m.y.begin(), m.y.end()));
    CHECK(i.bbox_min[2] == *std::min_element(m.z.begin(), m.z.end()));
    CHECK(i.mean_edge_length > 0);
  }
}

TEST_CASE("mesh_info: a quad torus keeps its quads; genus 1") {
  const Session s(make_quad_torus(12, 8));
  REQUIRE(s.has_polygons());
  const MeshInfo i = s.info();
  CHECK(i.n_faces == 96);
  CHECK(i.n_vertices == 96);
  CHECK(i.n_edges == 192);
  REQUIRE(i.face_degree_histogram.size() == 5);
  CHECK(i.face_degree_histogram[4] == 96);
  CHECK(i.euler_characteristic == 0);
  CHECK(i.genus == 1);
  // The C report: the same numbers, faces counted by degree.
  locus_session* c = nullptr;
  const Mesh m = make_quad_torus(12, 8);
  std::vector<double> xyz;
  for (int32_t v = 0; v < m.num_vertices(); ++v) xyz.insert(xyz.end(), {m.x[v], m.y[v], m.z[v]});
  REQUIRE(locus_session_create_polygons(xyz.data(), m.num_vertices(), m.face_offsets.data(), m.face_vertices.data(),
                                        m.num_faces(), &c) == LOCUS_OK);
  locus_info_report r;
  REQUIRE(locus_info_run(c, &r) == LOCUS_OK);
  CHECK(r.n_faces == 96);
  CHECK(r.quads == 96);
  CHECK(r.triangles == 0);
  CHECK(r.genus == 1);
  CHECK(r.manifold == 1);
  CHECK(r.first_unreferenced_vertex == -1);
  CHECK(locus_info_run(c, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_info_run(nullptr, &r) == LOCUS_BAD_USAGE);
  locus_session_destroy(c);
}

TEST_CASE("mesh_info: defects are counted and named, never refused") {
  Mesh m = make_icosphere(1);
  const int32_t nv = m.num_vertices();
  const int32_t a = m.f0[0], b = m.f1[0];
  m.add_vertex(3, 0, 0);  // the fin's apex: a third face on edge (a, b)
  m.add_triangle(a, b, nv);
  m.add_vertex(5, 5, 5);  // unreferenced
  const MeshInfo i = mesh_info(m);
  CHECK_FALSE(i.manifold);
  CHECK(i.non_manifold_edges >= 1);
  CHECK(((i.first_non_manifold_edge_v0 == a && i.first_non_manifold_edge_v1 == b) ||
         (i.first_non_manifold_edge_v0 == b && i.first_non_manifold_edge_v1 == a)));
  CHECK(i.unreferenced_vertices == 1);
  CHECK(i.first_unreferenced_vertex == nv + 1);
  CHECK(i.genus == -1);
  CHECK(i.bbox_max[0] == 5.0);
  // The default operator (auto) takes the mesh, and Session::info reports the same.
  const MeshInfo j = Session(Mesh(m)).info();
  CHECK(j.unreferenced_vertices == 1);
  CHECK(j.non_manifold_edges == i.non_manifold_edges);
}
