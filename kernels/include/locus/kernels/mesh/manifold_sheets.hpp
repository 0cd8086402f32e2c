// The manifold sheets of a triangle soup: the surface the CVT remesh (thesis
// §3.7) and the other commands that need a 2-manifold run on when an asset has
// non-manifold edges or vertices, zero-area faces, repeated faces,
// inconsistent orientation or unreferenced vertices. The soup is cut where it
// is not a manifold instead of refused:
// - a zero-area face whose vertex lies inside its longest edge (a T-junction
//   closed by a flat triangle) is removed and the face across that edge is
//   split at the vertex, so the surface stays closed; other zero-area faces,
//   faces that repeat a vertex and repeated faces are dropped;
// - around an edge of k > 2 faces the faces are glued in pairs, the pair that
//   continues most smoothly (their in-plane directions most opposite) first;
//   the faces left over keep the edge as a boundary;
// - faces are oriented consistently per sheet (the input's orientation where
//   most of the sheet's faces have it); a glued edge that would contradict the
//   orientation (a Moebius band) is cut;
// - every vertex becomes one vertex per fan of faces around it (a bowtie
//   vertex gives two), and unreferenced vertices are left out.
// On a clean, consistently oriented manifold mesh the sheets are the mesh.
#pragma once
#include <array>
#include <cstdint>

#include "locus/core/host_allocator.hpp"
#include "locus/mesh.hpp"

namespace locus {

struct ManifoldSheets {
  Mesh mesh;                              // triangles: manifold, oriented per component, no zero-area face
  HostVector<int32_t> vertex_of;          // per sheet vertex: the input vertex it copies
  HostVector<int32_t> face_of;            // per sheet face: the input face it lies in
  HostVector<std::array<double, 9>> corner_bary;  // per sheet face: its corners' barycentrics in face_of's face
  int64_t split_vertices = 0;     // sheet vertices beyond one per referenced input vertex
  int64_t cut_edges = 0;          // input edges of > 2 faces, or cut to keep the orientation
  int64_t flipped_faces = 0;      // sheet faces whose order is the reverse of their input face
  int64_t dropped_faces = 0;      // zero-area, repeated-vertex and repeated faces left out
  int64_t split_faces = 0;        // faces split at a T-junction's vertex
  int64_t unreferenced_vertices = 0;
  bool changed() const {
    return split_vertices || cut_edges || flipped_faces || dropped_faces || split_faces || unreferenced_vertices;
  }
};

// Throws BadInput for a face that is not a triangle or a non-finite coordinate.
// Deterministic; O((nv + nf) log nf).
ManifoldSheets manifold_sheets(const Mesh& m);

}  // namespace locus
