// Discrete operators on triangle meshes (thesis §3.3, eqs. 3.5, 3.6; §6.5 eqs. 6.1, 6.2).
//
// Sign convention: L_C is the cotan "Laplacian" with NEGATIVE diagonal
// ((L_C)_ij = (cot a_ij + cot b_ij)/2 for edges, (L_C)_ii = -sum_j (L_C)_ij), so
// -L_C is positive semidefinite and the heat operator M - t L_C is SPD for t > 0.
// Every operator needs a triangle mesh and throws BadInput naming the first face with
// another degree; the cotan-based ones also reject zero-area faces (their cotangents
// are undefined).
// All matrices are stored as the lower triangle (CscMatrix) with the SAME pattern
// (diagonal + every unique edge), so they can be combined value-wise.
#pragma once
#include <array>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

struct Edges;
struct EdgeIncidence;

// The operators below build the mesh's edge incidence (edge_incidence(m)) unless
// the caller passes the one it holds (MeshDerived::incidence), so that a
// pipeline builds it once (docs/ordering.md, "first answer").
// The lower CSC pattern every operator below shares (diagonal + edges, values
// zero): enough for an ordering and a symbolic factorization, which can then run
// beside the numeric assembly. `edges` sorted as unique_edges gives them.
CscMatrix operator_pattern(int32_t nv, const Edges& edges);
CscMatrix cotan_laplacian(const Mesh& m);                 // L_C
HostVector<double> lumped_mass(const Mesh& m);           // diag of M: one third of incident triangle areas
CscMatrix mass_matrix_as_csc(const Mesh& m);              // M on the pattern of L_C (zeros off the diagonal)
CscMatrix heat_operator(const Mesh& m, double t, const EdgeIncidence* inc = nullptr);  // M - t L_C
// -L_C + eps * M with eps relative to the operator's own scale,
// eps = rel * trace(-L_C) / trace(M), so the regularization (and the condition
// number) does not depend on the units of the mesh.
// Default rel = 1e-6, by measurement: the relative residual |Ax - b| / |b| of a
// sparse Cholesky solve (Eigen SimplicialLLT, random b) is about 2e-18 / rel on
// every mesh tried (armadillo in its units, area 3.8e4, and scaled to unit area;
// icospheres of levels 5 and 6; a 50k-point random sphere; a 300x100 torus):
// rel = 1e-8 gives 1.6e-10..3.8e-10, rel = 1e-6 gives 1.6e-12..3.7e-12, the 1e-10
// target with a 25x margin. The price: every eigenvalue of the pencil moves by eps,
// about rel * mean(diag(-L_C)) / mean(diag(M)) (grows with the vertex count).
constexpr double kLaplacianRegularization = 1e-6;
CscMatrix regularized_laplacian(const Mesh& m, double rel = kLaplacianRegularization, const EdgeIncidence* inc = nullptr);

// The vector area of face f: twice its area times its unit normal; for a
// polygon the sum over the fan from its first corner, the exact vector area
// of a planar polygon.
std::array<double, 3> face_vector_area(const Mesh& m, int32_t f);
// Per-vertex normals, unit length, 3*nv interleaved (x,y,z): the normalized sum of the
// vector areas of the incident faces (polygon faces allowed here); 0 at unreferenced
// vertices.
HostVector<double> area_weighted_normals(const Mesh& m);
// Mean-curvature normal vector -(M^{-1} L_C p)_i (eq. 6.1/6.2 up to sign: points
// outward on a convex surface, magnitude = 2 * mean curvature, i.e. 2/r on a sphere of
// radius r), 3*nv interleaved; 0 at unreferenced vertices.
HostVector<double> mean_curvature_normals(const Mesh& m, const EdgeIncidence* inc = nullptr);

}  // namespace locus
