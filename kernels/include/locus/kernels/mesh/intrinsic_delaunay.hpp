// Intrinsic Delaunay triangulation by edge flips (Bobenko & Springborn 2007;
// Sharp & Crane SGP 2020 §4.3): while some edge has opposite angles summing to more
// than pi (cot a + cot b < 0), flip it; lengths of new diagonals come from laying
// the two triangles out in the plane. A non-Delaunay edge of a valid intrinsic
// triangulation is always flippable, and the cotan weights of the result are all
// non-negative (thesis §3.3: eq. 3.5 then gives a maximum principle).
#pragma once
#include <cstdint>

#include "locus/kernels/mesh/intrinsic_triangulation.hpp"

namespace locus {

// An edge is flipped when cot a + cot b < -kDelaunayTolerance: below that the four
// vertices are cocircular to rounding, where flipping could cycle; the Laplacian
// treats such weights as 0 (robust_laplacian.hpp).
inline constexpr double kDelaunayTolerance = 1e-12;

struct DelaunayFlipStats {
  int64_t flips = 0;
  bool converged = true;  // false if the flip budget (50 per side + 1000) ran out
};

// Flips T in place to intrinsic Delaunay with a work queue of sides (every edge
// once at the start; the four edges around each flipped one after it). A flip is
// skipped when the two triangles share more than the edge (a vertex of degree
// one or two inside the quad), which no valid flip can change.
DelaunayFlipStats flip_to_intrinsic_delaunay(IntrinsicTriangulation& T);

}  // namespace locus
