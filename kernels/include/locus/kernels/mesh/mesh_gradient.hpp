// Per-triangle gradients and integrated vertex divergences of piecewise-linear
// functions on a triangle mesh (thesis §6.4.1, eq. 6.4; Crane et al.'s heat method).
//
// The gradient of the piecewise-linear function with corner values u_s in
// triangle k is g_k = sum_s u_s * grad(phi_s), grad(phi_s) = n_k x (v_{s+2} - v_{s+1}) / (2 A_k)
// (eq. 6.4). We store the three basis gradients per triangle once, so a
// gradient is nine multiply-adds and the divergence is its transpose:
//     (D X)_i = sum_{k containing i} A_k grad(phi_i)_k . X_k,
// the integrated divergence with the sign that makes (-L_C) d = D X the
// least-squares fit of grad d to X (the stiffness matrix -L_C has entries
// sum_k A_k grad(phi_i)_k . grad(phi_j)_k). Summing D X over the three
// corners of one triangle gives exactly zero (the basis gradients sum to 0), so
// the divergence of any field restricted to a set of whole triangles sums to 0.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/core/host_allocator.hpp"

#include "locus/mesh.hpp"

namespace locus {

struct TriangleGradients {
  int32_t nv = 0, nf = 0;
  HostVector<int32_t> tri;         // 3 * nf: corners of face k at tri[3k .. 3k+2]
  HostVector<double> area;         // nf
  HostVector<double> basis;        // 9 * nf: grad(phi_s) of corner s at basis[9k + 3s .. +2]
  HostVector<int64_t> vf_offsets;  // nv + 1: faces incident to each vertex (CSR), ascending face id
  HostVector<int32_t> vf_faces;

  // g = sum_s u_s grad(phi_s) in face k.
  void gradient(int32_t k, double u0, double u1, double u2, double g[3]) const {
    const double* b = basis.data() + 9 * static_cast<int64_t>(k);
    for (int c = 0; c < 3; ++c) g[c] = u0 * b[c] + u1 * b[3 + c] + u2 * b[6 + c];
  }
};

// Fills g.vf_offsets / g.vf_faces from g.tri (a counting sort: faces ascending
// per vertex; a face of a repeated vertex appears twice in its list).
void index_vertex_faces(TriangleGradients& g);

// Needs a triangle mesh without zero-area faces (throws Error(BadInput) naming
// the first offending face); positions must be finite. O(nv + nf).
TriangleGradients triangle_gradients(const Mesh& m);
// The same with the mean edge length h of m already known (MeshDerived::h):
// h only scales the zero-area threshold.
TriangleGradients triangle_gradients(const Mesh& m, double h);

}  // namespace locus
