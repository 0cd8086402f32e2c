// Tests for kernels/mesh/mesh_derived.{hpp,cpp}: every field equals the value of
// its own function (unique_edges, vertex_adjacency, mean_edge_length,
// lumped_mass, connected_components), bit for bit.
#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

using namespace locus;

namespace {
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
}  // namespace

TEST_CASE("derive_mesh: the separate functions' values, bit for bit") {
  Mesh two = make_random_sphere(500, 2);
  const Mesh other = make_torus(12, 8);
  const int32_t shift = two.num_vertices();
  for (int32_t v = 0; v < other.num_vertices(); ++v) two.add_vertex(other.x[v] + 3, other.y[v], other.z[v]);
  for (int32_t f = 0; f < other.num_faces(); ++f)
    two.add_triangle(other.f0[f] + shift, other.f1[f] + shift, other.f2[f] + shift);
  for (const Mesh& m : {make_icosphere(2), make_disk(9, 0.2, 3), two}) {
    const MeshDerived d = derive_mesh(m);
    CHECK(d.nv == m.num_vertices());
    CHECK(d.nf == m.num_faces());
    const Edges e = unique_edges(m);
    CHECK(d.incidence.edges.e0 == e.e0);
    CHECK(d.incidence.edges.e1 == e.e1);
    CHECK(d.incidence.edges.face_count == e.face_count);
    const Adjacency a = vertex_adjacency(m);
    CHECK(d.adjacency.offsets == a.offsets);
    CHECK(d.adjacency.neighbors == a.neighbors);
    CHECK(same_bits(d.h, mean_edge_length(m)));
    const auto mass = lumped_mass(m);
    REQUIRE(d.mass.size() == mass.size());
    for (size_t k = 0; k < mass.size(); ++k) CHECK(same_bits(d.mass[k], mass[k]));
    std::vector<int32_t> comp;
    CHECK(d.components == connected_components(m, comp));
    CHECK(d.component == comp);
    CHECK_FALSE(requirements_checked(d, MeshRequirements{}));
    CHECK(requirements_checked(d, MeshRequirements{false, false, false, false, false, false, false}));
  }
  CHECK(derive_mesh(two).components == 2);
  // Polygon meshes: no mass, everything else.
  const Mesh quads = make_quad_torus(6, 4);
  const MeshDerived q = derive_mesh(quads);
  CHECK(q.mass.empty());
  CHECK(same_bits(q.h, mean_edge_length(quads)));
  CHECK_THROWS_AS(check_derived_of(q, make_icosphere(1), "test"), Error);
}
