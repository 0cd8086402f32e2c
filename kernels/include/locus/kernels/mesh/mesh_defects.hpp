// Which defects a triangle mesh has, the ones the cotan operator or the heat
// method cannot take and the robust Laplacian (robust_laplacian.hpp) can: a count
// and the first offender of each kind, in O(nv + nf) (one edge incidence and the
// one-pass report of mesh_topology.hpp, plus a pass over the faces for needles).
#pragma once
#include <cstdint>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"

namespace locus {

// A needle: a face with an angle within kNeedleAngle of 0 or pi (radians) and an
// area above the zero-area threshold; the cotangent there is beyond 1e6 and the
// heat method's accuracy is lost (the same bound the heat geodesic refuses by).
inline constexpr double kNeedleAngle = 1e-6;

struct MeshDefects {
  // Edges shared by more than two faces; first: its vertices and face count.
  int64_t non_manifold_edges = 0;
  int64_t first_non_manifold_edge_v0 = -1, first_non_manifold_edge_v1 = -1, first_non_manifold_edge_faces = 0;
  // Vertices whose faces form more than one fan (a bowtie, or a vertex of a
  // non-manifold edge); first: the vertex and its fan count.
  int64_t non_manifold_vertices = 0;
  int64_t first_non_manifold_vertex = -1, first_non_manifold_vertex_fans = 0;
  // Faces of zero area (mesh_topology's kDegenerateAreaRelative * h^2), including
  // faces that repeat a vertex id.
  int64_t zero_area_faces = 0;
  int64_t first_zero_area_face = -1;
  // Needles (kNeedleAngle); first: the face and the vertex of its smallest or largest angle.
  int64_t needle_faces = 0;
  int64_t first_needle_face = -1, first_needle_vertex = -1;
  // Edges of exactly two faces that run them the same way; first: its vertices.
  int64_t inconsistent_orientation_edges = 0;
  int64_t first_inconsistent_edge_v0 = -1, first_inconsistent_edge_v1 = -1;
  // Vertices of no face.
  int64_t unreferenced_vertices = 0;
  int64_t first_unreferenced_vertex = -1;

  bool any() const {
    return non_manifold_edges || non_manifold_vertices || zero_area_faces || needle_faces ||
           inconsistent_orientation_edges || unreferenced_vertices;
  }
};

// Needs a triangle mesh with finite coordinates (throws BadInput otherwise, naming
// the face or vertex).
MeshDefects detect_mesh_defects(const Mesh& m);
MeshDefects detect_mesh_defects(const Mesh& m, const EdgeIncidence& inc, const MeshReport& report);

}  // namespace locus
