// The robust Laplacian (Sharp & Crane, "A Laplacian for Nonmanifold Triangle
// Meshes", SGP 2020): tufted cover -> intrinsic mollification -> intrinsic
// Delaunay flips -> cotan Laplacian and lumped mass (thesis §3.3, eqs. 3.5, 3.6)
// of the intrinsic triangles, halved for the cover's two sheets. On a clean mesh
// whose triangulation is already Delaunay (and with no mollification) this is the
// cotan operator of mesh_operators.hpp up to rounding.
#include "locus/kernels/mesh/robust_laplacian.hpp"

#include <algorithm>
#include <vector>

#include "locus/kernels/mesh/tufted_cover.hpp"

namespace locus {

namespace {

// Lower CSC from entries (i, j, w) with i != j and one diagonal value per column:
// a counting sort by the smaller index, then an insertion sort of each column (a
// vertex has a handful of intrinsic edges) merging repeated pairs (an edge glued
// on several sheets, or two intrinsic edges between the same vertices).
CscMatrix lower_from_edges(int32_t n, const std::vector<int32_t>& ii, const std::vector<int32_t>& jj,
                           const std::vector<double>& vv, const std::vector<double>& diag) {
  CscMatrix A;
  A.nrows = A.ncols = n;
  A.colptr.assign(static_cast<size_t>(n) + 1, 0);
  for (size_t k = 0; k < ii.size(); ++k) ++A.colptr[std::min(ii[k], jj[k]) + 1];
  for (int32_t j = 0; j < n; ++j) A.colptr[j + 1] += A.colptr[j] + 1;
  A.rowind.resize(static_cast<size_t>(A.colptr[n]));
  A.values.resize(static_cast<size_t>(A.colptr[n]));
  std::vector<int64_t> pos(static_cast<size_t>(n));
  for (int32_t j = 0; j < n; ++j) {
    A.rowind[A.colptr[j]] = j;
    A.values[A.colptr[j]] = diag[j];
    pos[j] = A.colptr[j] + 1;
  }
  for (size_t k = 0; k < ii.size(); ++k) {
    const int32_t lo = std::min(ii[k], jj[k]);
    A.rowind[pos[lo]] = std::max(ii[k], jj[k]);
    A.values[pos[lo]++] = vv[k];
  }
  int64_t out = 0;
  for (int32_t j = 0; j < n; ++j) {
    const int64_t b = A.colptr[j], e = A.colptr[j + 1];
    for (int64_t p = b + 2; p < e; ++p) {  // the diagonal stays first
      const int32_t r = A.rowind[p];
      const double v = A.values[p];
      int64_t q = p;
      for (; q > b + 1 && A.rowind[q - 1] > r; --q) A.rowind[q] = A.rowind[q - 1], A.values[q] = A.values[q - 1];
      A.rowind[q] = r, A.values[q] = v;
    }
    A.colptr[j] = out;
    for (int64_t p = b; p < e; ++p) {
      if (p > b && out > A.colptr[j] && A.rowind[out - 1] == A.rowind[p]) {
        A.values[out - 1] += A.values[p];
      } else {
        A.rowind[out] = A.rowind[p];
        A.values[out++] = A.values[p];
      }
    }
  }
  A.colptr[n] = out;
  A.rowind.resize(static_cast<size_t>(out));
  A.values.resize(static_cast<size_t>(out));
  return A;
}

}  // namespace

void assemble_intrinsic_laplacian(const IntrinsicTriangulation& T, CscMatrix& L, HostVector<double>& mass) {
  const int32_t n = T.num_vertices, ns = static_cast<int32_t>(T.vertex.size());
  mass.assign(static_cast<size_t>(n), 0.0);
  std::vector<double> diag(static_cast<size_t>(n), 0.0);
  std::vector<int32_t> ii, jj;
  std::vector<double> vv;
  ii.reserve(static_cast<size_t>(ns / 2));
  jj.reserve(ii.capacity());
  vv.reserve(ii.capacity());
  for (int32_t s = 0; s < ns; ++s) {
    if (s % 3 == 0) {  // a third of the area per corner, half for the two sheets
      const double* l = T.length.data() + s;
      const double third = intrinsic_triangle_area(l[0], l[1], l[2]) / 6.0;
      for (int k = 0; k < 3; ++k) mass[T.vertex[s + k]] += third;
    }
    const int32_t t = T.twin[s];
    if (t < s) continue;
    const int32_t i = T.vertex[s], j = T.vertex[t];
    if (i == j) continue;  // a loop edge: w (u_i - u_i) = 0
    const double cot_sum = cotan_opposite(T, s) + cotan_opposite(T, t);
    // Below the flip tolerance the quad is cocircular to rounding: the weight is 0.
    const double w = cot_sum < 0.0 && cot_sum >= -kDelaunayTolerance ? 0.0 : 0.25 * cot_sum;
    ii.push_back(i);
    jj.push_back(j);
    vv.push_back(w);
    diag[i] -= w;
    diag[j] -= w;
  }
  L = lower_from_edges(n, ii, jj, vv, diag);
}

RobustOperators robust_laplacian(const Mesh& m, const RobustLaplacianOptions& opt) {
  RobustOperators out;
  out.triangulation = tufted_cover(m);
  IntrinsicTriangulation& T = out.triangulation;
  out.mollify_epsilon = mollify_intrinsic(T, opt.mollify_relative);
  out.flips = flip_to_intrinsic_delaunay(T);
  assemble_intrinsic_laplacian(T, out.L, out.mass);
  // Isolated vertices: a decoupled, well-scaled pivot (robust_laplacian.hpp).
  const int32_t n = T.num_vertices;
  double total = 0.0;
  int32_t with_area = 0;
  std::vector<char> in_face(static_cast<size_t>(n), 0);
  for (const int32_t v : T.vertex) in_face[v] = 1;
  for (int32_t v = 0; v < n; ++v)
    if (in_face[v]) {
      total += out.mass[v];
      ++with_area;
    }
  const double fill = with_area > 0 && total > 0.0 ? total / with_area : 1.0;
  for (int32_t v = 0; v < n; ++v)
    if (!in_face[v]) {
      out.mass[v] = fill;
      ++out.isolated_vertices;
    }
  out.M = out.L;
  std::fill(out.M.values.begin(), out.M.values.end(), 0.0);
  for (int32_t j = 0; j < n; ++j) out.M.values[out.M.colptr[j]] = out.mass[j];
  return out;
}

}  // namespace locus
