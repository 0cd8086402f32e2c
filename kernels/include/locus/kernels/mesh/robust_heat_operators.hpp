// The heat method's operators on the robust Laplacian (robust_laplacian.hpp;
// Sharp & Crane, SGP 2020, §5 "heat method on nonmanifold meshes"): the heat
// operator M - tL (thesis eq. 6.3), the regularized Poisson operator -L + eps M
// (eq. 6.6) and the per-triangle gradient bases (eq. 6.4) of the intrinsic
// triangles of the tufted cover, so that the gradient of the heat and the
// divergence of its unit direction run on the same triangles L is built from,
// not on the extrinsic soup (whose fins, needles and zero-area faces have no
// usable gradient).
#pragma once
#include "locus/kernels/mesh/mesh_gradient.hpp"
#include "locus/kernels/mesh/robust_laplacian.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

// M - t L on L's pattern (lower CSC, diagonal first). t >= 0 and finite
// (Error(BadUsage) otherwise).
CscMatrix robust_heat_operator(const RobustOperators& R, double t);

// -L + eps M with eps = rel * trace(-L) / trace(M), as mesh_operators.hpp's
// regularized_laplacian does for the cotan operator. rel > 0.
CscMatrix robust_regularized_laplacian(const RobustOperators& R, double rel);

// Gradient bases of every intrinsic triangle, each laid out in its own plane
// from its side lengths (corner 0 at the origin, corner 1 on the x axis, z = 0),
// the layout mesh_gradient.hpp's TriangleGradients describes: a gradient and
// a divergence are the same arithmetic as on an extrinsic mesh. `area` holds
// area_scale times each triangle's area: 1/2 matches robust_laplacian's L and M
// (the cover counts the surface twice), so that the divergence of a field is
// consistent with L. A triangle without area (lengths violating the triangle
// inequality, which mollification prevents) gets zero bases and area.
// Vertex ids may repeat within a triangle (an intrinsic edge may join a vertex
// to itself after flips). O(#triangles).
TriangleGradients intrinsic_triangle_gradients(const IntrinsicTriangulation& T, double area_scale = 0.5);

}  // namespace locus
