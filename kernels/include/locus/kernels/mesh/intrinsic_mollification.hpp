// Intrinsic mollification (Sharp & Crane, "A Laplacian for Nonmanifold Triangle
// Meshes", SGP 2020, §4.5): the smallest epsilon >= 0 such that adding it to
// every edge length gives every triangle the strict triangle inequality with a
// margin delta, a_ij + a_jk - a_ki >= delta for every corner. Adding the same
// epsilon everywhere keeps the lengths consistent across glued sides and changes
// a well-shaped mesh by O(epsilon / h) only; zero-area and needle triangles get a
// positive area and bounded cotangents.
#pragma once
#include "locus/kernels/mesh/intrinsic_triangulation.hpp"

namespace locus {

// delta = kMollifyRelative * (mean side length), the paper's default factor
// (geometry-central's robust Laplacian uses the same 1e-5). On the clean meshes of
// the tests (icospheres, grids) every margin exceeds it, so epsilon is 0 and the
// operator is exactly the cotan one.
inline constexpr double kMollifyRelative = 1e-5;

// Adds epsilon to every length of T and returns it. relative = 0 only repairs
// violated inequalities (epsilon = the worst violation, which leaves a zero-area
// triangle flat: only for tests on meshes known to be non-degenerate).
double mollify_intrinsic(IntrinsicTriangulation& T, double relative = kMollifyRelative);

}  // namespace locus
