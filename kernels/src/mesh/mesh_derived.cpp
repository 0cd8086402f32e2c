// Derived mesh data computed once (kernels/include/locus/kernels/mesh/mesh_derived.hpp).
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/core/host_allocator.hpp"

#include <string>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"

namespace locus {

MeshDerived derive_mesh(const Mesh& m) { return derive_mesh(m, edge_incidence(m)); }  // validates the arrays

MeshDerived derive_mesh(const Mesh& m, EdgeIncidence incidence) {
  MeshDerived d;
  d.incidence = std::move(incidence);
  complete_derived(m, d);
  return d;
}

void complete_derived(const Mesh& m, MeshDerived& d) {
  if (d.incidence.corner_edge.size() != m.face_vertices.size())
    fail(ErrorCode::BadUsage, "derive_mesh: the edge incidence belongs to another mesh");
  d.nv = m.num_vertices();
  d.nf = m.num_faces();
  d.adjacency = vertex_adjacency(m, d.incidence.edges);
  d.h = mean_edge_length(m, d.incidence.edges);
  if (m.is_triangle_mesh()) d.mass = lumped_mass(m);
  std::vector<int32_t> component;
  d.components = connected_components(m, component);
  d.component = component;
}

bool requirements_checked(const MeshDerived& d, const MeshRequirements& need) {
  const MeshRequirements& c = d.checked;
  return (!need.triangles || c.triangles) && (!need.manifold || c.manifold) &&
         (!need.no_degenerate_faces || c.no_degenerate_faces) &&
         (!need.no_unreferenced_vertices || c.no_unreferenced_vertices) && (!need.connected || c.connected) &&
         (!need.closed || c.closed) && (!need.finite_coordinates || c.finite_coordinates);
}

void check_derived_of(const MeshDerived& d, const Mesh& m, const char* who) {
  if (d.nv != m.num_vertices() || d.nf != m.num_faces())
    fail(ErrorCode::BadUsage, std::string(who) + ": the derived mesh data (" + std::to_string(d.nv) + " vertices, " +
                                  std::to_string(d.nf) + " faces) belongs to another mesh (" +
                                  std::to_string(m.num_vertices()) + " vertices, " + std::to_string(m.num_faces()) +
                                  " faces)");
}

}  // namespace locus
