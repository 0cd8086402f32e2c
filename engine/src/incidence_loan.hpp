// The edge incidence (and for the factorization the vertex adjacency) of a
// mesh's derived data set aside while nothing reads it
// (thesis §3.7.1: between the assembly of the cells' operator M - tL and the
// restricted dual, Lloyd's iterations read the vertex adjacency, the masses and
// the components only). At 416k vertices the edges and corner_edge are 25 MB
// of a remesh's peak; rebuilding them costs one edge incidence (~0.1 s).
// Internal to the engine: only for derived data nobody else reads meanwhile
// (SessionOptions::exclusive).
#pragma once
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/mesh.hpp"

namespace locus {

class IncidenceLoan {
 public:
  // d: the derived data of m (check_and_derive's or derive_mesh's).
  IncidenceLoan(const Mesh& m, MeshDerived& d) : m_(m), d_(d) {}
  IncidenceLoan(const IncidenceLoan&) = delete;
  IncidenceLoan& operator=(const IncidenceLoan&) = delete;
  // Restores what was released (the owner may read the incidence after an error).
  ~IncidenceLoan();

  // Frees d.incidence (its edges, corner_edge and the edge-to-corner CSR if held).
  void release();
  // Frees d.adjacency too, for the factorization, which reads neither (13 MB
  // of its peak at 416k vertices); restore_adjacency rebuilds it from the
  // faces (the same arrays as vertex_adjacency) before Lloyd reads it.
  void release_adjacency();
  void restore_adjacency();
  // d.incidence as it was: edge_incidence(m), its edge-to-corner CSR dropped
  // when it had been (drop_edge_corners; then rebuilt from d.adjacency, the
  // same arrays with less transient memory), and d.adjacency if it was out.
  // Nothing when not released.
  void restore();
  bool released() const { return released_; }
  // restore() reads m.face_vertices (edge_incidence: the CSR was held);
  // otherwise a triangle mesh's f0/f1/f2 only.
  bool restore_reads_corners() const { return released_ && had_corners_; }

 private:
  const Mesh& m_;
  MeshDerived& d_;
  bool released_ = false;
  bool adjacency_out_ = false;
  bool had_corners_ = false;
};

}  // namespace locus
