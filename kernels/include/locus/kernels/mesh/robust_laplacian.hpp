// The robust Laplacian and mass matrix (Sharp & Crane, "A Laplacian for
// Nonmanifold Triangle Meshes", SGP 2020): the cotan Laplacian (thesis §3.3,
// eq. 3.5) and lumped mass (eq. 3.6) of the intrinsic Delaunay triangulation of
// the mesh's tufted cover, after intrinsic mollification. Defined on every
// triangle soup: non-manifold edges and vertices, zero-area and needle faces,
// inconsistent orientation, repeated faces, unreferenced vertices.
//
// Same conventions as mesh_operators.hpp: L has a NEGATIVE diagonal, non-negative
// off-diagonal weights and zero row sums (-L is positive semidefinite); both
// matrices are n x n lower CSC (rows ascending, diagonal first) on one pattern,
// so M - t L goes through the ordering, factorization and solves unchanged. The
// pattern is the intrinsic edges' (an edge made by a flip joins vertices that
// share no mesh edge), not operator_pattern's.
#pragma once
#include <cstdint>

#include "locus/kernels/mesh/intrinsic_delaunay.hpp"
#include "locus/kernels/mesh/intrinsic_mollification.hpp"
#include "locus/kernels/mesh/intrinsic_triangulation.hpp"
#include "locus/mesh.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

struct RobustLaplacianOptions {
  // delta of the mollification, relative to the mean edge length (0: none on a
  // non-degenerate mesh, for comparisons with the cotan operator).
  double mollify_relative = kMollifyRelative;
};

struct RobustOperators {
  CscMatrix L;                  // n x n, lower, negative diagonal
  CscMatrix M;                  // lumped mass on L's pattern (zeros off the diagonal)
  HostVector<double> mass;      // diag of M
  // The intrinsic Delaunay triangulation of the tufted cover (two sheets: an
  // integral over it counts the surface twice, so L and M are halved sums).
  // The heat method's gradient and divergence run on its triangles.
  IntrinsicTriangulation triangulation;
  double mollify_epsilon = 0.0;  // added to every edge length
  DelaunayFlipStats flips;
  // Vertices in no kept triangle (unreferenced, or only in triangles that repeat a
  // vertex id): their row of L is zero and their mass is the mean mass of the
  // others (1 when there are none), so M - t L stays positive definite and their
  // decoupled pivots are well scaled; a caller reports them as NaN.
  int32_t isolated_vertices = 0;
};

// O(nv + nf) plus the flips (none on a mesh that is already Delaunay, about one
// edge in ten on a scanned mesh).
// Throws BadInput for a non-triangle face or a non-finite coordinate.
RobustOperators robust_laplacian(const Mesh& m, const RobustLaplacianOptions& opt = {});

// The Laplacian of an intrinsic triangulation as robust_laplacian assembles it,
// halved for the two sheets (exposed for tests and for callers that flip
// themselves). mass gets one third of each triangle's area per corner, halved.
void assemble_intrinsic_laplacian(const IntrinsicTriangulation& T, CscMatrix& L, HostVector<double>& mass);

}  // namespace locus
