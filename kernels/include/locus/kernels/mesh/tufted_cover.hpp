// The tufted cover of a triangle soup (Sharp & Crane, "A Laplacian for
// Nonmanifold Triangle Meshes", SGP 2020, §4.2): every triangle taken twice,
// once per orientation, and around every edge the 2k sides of its k triangles
// glued in pairs so that the result is a closed, oriented, manifold intrinsic
// triangulation over the same vertices. Its Laplacian is twice the cotan
// Laplacian on a clean manifold mesh (two sheets), and exists on any soup.
#pragma once
#include "locus/kernels/mesh/intrinsic_triangulation.hpp"
#include "locus/mesh.hpp"

namespace locus {

// Faces 2q and 2q + 1 of the cover are the q-th kept triangle (a, b, c) and its
// reverse (a, c, b). Kept: every triangle with three distinct vertex ids (one that
// repeats an id has no area and no edge to glue; it is dropped). Around an edge
// shared by k kept triangles, taken in face order, the copy of triangle i that
// runs the edge from its smaller to its larger vertex is glued to the copy of
// triangle i + 1 (mod k) that runs it the other way: an edge of one triangle
// (boundary) glues the triangle's two copies, a consistently oriented manifold
// edge gives two separate sheets, and an inconsistently oriented one crosses
// them. Lengths are the Euclidean lengths of the mesh's edges.
// Throws BadInput for a non-triangle face or a non-finite coordinate. O(nv + nf).
IntrinsicTriangulation tufted_cover(const Mesh& m);

}  // namespace locus
