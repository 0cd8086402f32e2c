// Derived mesh data computed once: unique edges, vertex adjacency, mean edge
// length h, lumped mass and connected components, by one function, so that a
// caller holding them (the Session, a pipeline running several steps) hands
// them down instead of every step rebuilding the edge incidence.
//
// Each field is the value of its own mesh_topology / mesh_operators function,
// bit for bit (h by the same summation over the same edge order):
//   incidence  = edge_incidence(m)            (incidence.edges = unique_edges(m))
//   adjacency  = vertex_adjacency(m)          (built from incidence.edges)
//   h          = mean_edge_length(m)          (mean_edge_length(m, incidence.edges))
//   mass       = lumped_mass(m)               (triangle meshes; empty otherwise)
//   component  = connected_components(m, .)   (components: their count)
//
// `checked` records which MeshRequirements the caller verified on m (nothing by
// default: derive_mesh checks only the arrays). A pipeline given derived data
// skips its own check_requirements when `checked` covers what it needs.
// `report` is that check's analyze_mesh(m), when the caller made one: a
// command reads the input's topology from it again (no second analysis).
// The data belongs to one mesh and one set of positions: rebuild it when either
// changes.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "locus/core/host_allocator.hpp"

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"

namespace locus {

struct MeshDerived {
  int32_t nv = 0, nf = 0;
  EdgeIncidence incidence;  // the operators and checks take it instead of rebuilding it
  Adjacency adjacency;
  double h = 0;                    // mean edge length
  HostVector<double> mass;        // lumped mass (triangle meshes), else empty
  HostVector<int32_t> component;  // per vertex, -1 for unreferenced vertices
  int32_t components = 0;
  MeshRequirements checked{false, false, false, false, false, false, false};
  std::optional<MeshReport> report;
};

// BadInput for malformed arrays (validate_mesh_arrays) or a face of non-finite
// area (lumped_mass's check).
MeshDerived derive_mesh(const Mesh& m);
// The same from an incidence the caller already built (edge_incidence(m)).
MeshDerived derive_mesh(const Mesh& m, EdgeIncidence incidence);
// Fills every field but `incidence` (which must be edge_incidence(m)) and `checked`;
// reads nothing else of d, so a check of d.incidence can run beside it.
void complete_derived(const Mesh& m, MeshDerived& d);

// True when every requirement in `need` is among those in d.checked.
bool requirements_checked(const MeshDerived& d, const MeshRequirements& need);

// BadUsage unless d was derived from a mesh of m's size (a cheap guard, not a proof).
void check_derived_of(const MeshDerived& d, const Mesh& m, const char* who);

}  // namespace locus
