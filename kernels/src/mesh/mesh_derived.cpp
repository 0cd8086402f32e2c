// Derived mesh data computed once (kernels/include/locus/kernels/mesh/mesh_derived.hpp).
#include "locus/kernels/mesh/mesh_derived.hpp"

#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"

namespace locus {

MeshDerived derive_mesh(const Mesh& m) {
  MeshDerived d;
  d.nv = m.num_vertices();
  d.nf = m.num_faces();
  d.edges = unique_edges(m);  // validates the arrays
  d.adjacency = vertex_adjacency(m, d.edges);
  d.h = mean_edge_length(m, d.edges);
  if (m.is_triangle_mesh()) d.mass = lumped_mass(m);
  d.components = connected_components(m, d.component);
  return d;
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
