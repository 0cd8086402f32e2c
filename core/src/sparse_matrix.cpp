// CSC helpers (core/include/locus/sparse_matrix.hpp).
#include "locus/sparse_matrix.hpp"

#include <algorithm>

#include "locus/error.hpp"

namespace locus {

CscMatrix lower_from_triplets(int32_t n, const std::vector<int32_t>& ii, const std::vector<int32_t>& jj,
                              const std::vector<double>& vv) {
  if (ii.size() != jj.size() || ii.size() != vv.size())
    fail(ErrorCode::BadUsage, "lower_from_triplets: triplet arrays differ in length");
  CscMatrix A;
  A.nrows = A.ncols = n;
  // Counting sort by column, then sort rows within columns and merge duplicates.
  std::vector<int64_t> cnt(static_cast<size_t>(n) + 1, 0);
  for (size_t k = 0; k < ii.size(); ++k) {
    int32_t i = ii[k], j = jj[k];
    if (i < 0 || j < 0 || i >= n || j >= n) fail(ErrorCode::BadUsage, "lower_from_triplets: index out of range");
    ++cnt[static_cast<size_t>(std::min(i, j)) + 1];
  }
  for (int32_t j = 0; j < n; ++j) cnt[j + 1] += cnt[j];
  std::vector<int32_t> r(ii.size());
  std::vector<double> v(ii.size());
  std::vector<int64_t> pos(cnt.begin(), cnt.end() - 1);
  for (size_t k = 0; k < ii.size(); ++k) {
    int32_t i = ii[k], j = jj[k];
    if (i < j) std::swap(i, j);
    const int64_t p = pos[j]++;
    r[p] = i;
    v[p] = vv[k];
  }
  A.colptr.assign(static_cast<size_t>(n) + 1, 0);
  A.rowind.reserve(ii.size());
  A.values.reserve(ii.size());
  std::vector<std::pair<int32_t, double>> col;
  for (int32_t j = 0; j < n; ++j) {
    col.clear();
    for (int64_t p = cnt[j]; p < cnt[j + 1]; ++p) col.emplace_back(r[p], v[p]);
    std::sort(col.begin(), col.end(), [](auto& a, auto& b) { return a.first < b.first; });
    for (size_t q = 0; q < col.size(); ++q) {
      if (!A.rowind.empty() && static_cast<int64_t>(A.rowind.size()) > A.colptr[j] && A.rowind.back() == col[q].first)
        A.values.back() += col[q].second;
      else {
        A.rowind.push_back(col[q].first);
        A.values.push_back(col[q].second);
      }
    }
    A.colptr[j + 1] = static_cast<int64_t>(A.rowind.size());
  }
  return A;
}

void symmetric_multiply(const CscMatrix& A, const double* x, double* y) {
  std::fill(y, y + A.nrows, 0.0);
  for (int32_t j = 0; j < A.ncols; ++j) {
    const double xj = x[j];
    double acc = 0.0;
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      const double a = A.values[p];
      y[i] += a * xj;
      if (i != j) acc += a * x[i];
    }
    y[j] += acc;
  }
}

CscMatrix combine_same_pattern(double a, const CscMatrix& A, double b, const CscMatrix& B) {
  if (A.colptr != B.colptr || A.rowind != B.rowind)
    fail(ErrorCode::BadUsage, "combine_same_pattern: matrices have different sparsity patterns");
  CscMatrix C = A;
  for (size_t k = 0; k < C.values.size(); ++k) C.values[k] = a * A.values[k] + b * B.values[k];
  return C;
}

}  // namespace locus
