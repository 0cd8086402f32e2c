// A_II, the principal submatrix the factor-once update factors (thesis §5.4),
// read from A: gathered through a local index, or, for the prepared updater,
// read from A stored in L's column order together with the assembly map of the
// restricted factor. Internal to kernels/src/update.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus::update_detail {

// A_II from a local index (local(v) = position of v in I, -1 outside), which
// is increasing on I, so rows stay sorted and lower. One pass with an upper
// bound of the entries: the columns of a scattered I are cache misses, read once.
template <class Local>
CscMatrix submatrix_with(const CscMatrix& A, std::span<const int32_t> vertices, Local local) {
  const int32_t m = static_cast<int32_t>(vertices.size());
  int64_t bound = 0;
  for (const int32_t v : vertices) bound += A.colptr[v + 1] - A.colptr[v];
  CscMatrix B;
  B.nrows = B.ncols = m;
  B.colptr.resize(static_cast<size_t>(m) + 1);
  B.colptr[0] = 0;
  B.rowind.resize(static_cast<size_t>(bound));
  B.values.resize(static_cast<size_t>(bound));
  int64_t q = 0;
  for (int32_t a = 0; a < m; ++a) {
    const int32_t v = vertices[a];
    for (int64_t p = A.colptr[v]; p < A.colptr[v + 1]; ++p) {
      const int32_t r = local(A.rowind[p]);
      if (r >= 0) {
        B.rowind[q] = r;
        B.values[q] = A.values[p];
        ++q;
      }
    }
    B.colptr[a + 1] = q;
  }
  B.rowind.resize(static_cast<size_t>(q));
  B.values.resize(static_cast<size_t>(q));
  return B;
}

inline CscMatrix submatrix_from_map(const CscMatrix& A, std::span<const int32_t> vertices, const std::vector<int32_t>& local) {
  return submatrix_with(A, vertices, [&](int32_t v) { return local[v]; });
}


// Error(Numerical) for a non-finite entry of A_II. A type of its own so that
// the recomputation, whose assembler may raise it, passes it on unchanged
// instead of renaming it as a pivot failure; update() hands it to the caller
// as a plain Error.
class NotFiniteEntry : public Error {
 public:
  using Error::Error;
};

// A non-finite entry of A_II, named by its vertices (local indices a and b,
// in A's numbering or the caller's ids): a NaN or infinity would pass the
// pivots silently and poison every solve.
[[noreturn]] void fail_not_finite(std::span<const int32_t> vertices, std::span<const int32_t> ids, int32_t a, int32_t b);

// A_II (lower CSC, local numbering) and the assembly map of the restricted
// factor Sp, read from A stored in L's column order (ap: column c = rows r >= c).
// The columns of a patch are a few contiguous ranges of L's order, so this
// reads A with the factor's locality. gcol: restricted column -> L's column;
// col_new: L's column -> restricted column (-1 outside I). The entries are
// visited supernode by supernode (which groups the assembly map), then put in
// A_II's column order, rows ascending, by two stable counting sorts.
void assemble_from_factor_order(SymbolicFactor& Sp, const std::vector<int32_t>& gcol, const std::vector<int32_t>& col_new,
                                const std::vector<int64_t>& ap_ptr, const std::vector<int32_t>& ap_row,
                                const std::vector<double>& ap_val, const std::vector<int32_t>& vertices,
                                std::span<const int32_t> ids, CscMatrix& B);

}  // namespace locus::update_detail
