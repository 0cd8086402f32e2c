// The sizes of mesh a double-precision operator can be built for. Areas (the
// mass matrix), squared edge lengths (cotangents, the mean edge length), heat
// times t = c h^2 and squared distances are products of two coordinate
// differences: beyond about 1e154 they overflow to infinity, below about
// 1e-154 they underflow to zero, and every later check then names a symptom
// ("face 0 has zero area", "not positive definite", "mesh has no area")
// instead of the cause. The kernels scale their cross products by powers of two
// (power_of_two_scale), so every size within the range gives the results of
// the unit-size mesh, scaled; the range keeps a margin of 1e4 in the squares
// for sums over many faces and heat times up to 1e6 h^2.
#pragma once
#include <string>

#include "locus/mesh.hpp"

namespace locus {

// The bounding-box diagonal a mesh may have.
inline constexpr double kMinMeshSize = 1e-150;
inline constexpr double kMaxMeshSize = 1e150;

// Diagonal of the bounding box of m's vertices (non-finite coordinates skipped),
// computed without overflow or underflow at any scale; +inf when it exceeds the
// largest double. 0 for a mesh without vertices or whose vertices coincide.
double bounding_box_diagonal(const Mesh& m);
// The same from a bounding box (min and max corners).
double bounding_box_diagonal(const double lo[3], const double hi[3]);

// Throws Error(BadInput) naming the mesh, its size and the range
// [kMinMeshSize, kMaxMeshSize] unless the diagonal lies in it (a diagonal of 0,
// all vertices at one point, is left to the degenerate-face checks, which name
// a face). `diagonal` is bounding_box_diagonal(m).
void check_mesh_size(const Mesh& m, double diagonal);
inline void check_mesh_size(const Mesh& m) { check_mesh_size(m, bounding_box_diagonal(m)); }

}  // namespace locus
