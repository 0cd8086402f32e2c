// Compressed sparse column matrices.
//
// Symmetric matrices store the lower triangle only (row >= col in every column),
// rows sorted ascending within a column, no duplicates.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/core/host_allocator.hpp"

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API CscMatrix {
  int32_t nrows = 0, ncols = 0;
  HostVector<int64_t> colptr{0};  // ncols + 1
  HostVector<int32_t> rowind;     // colptr[ncols]
  HostVector<double> values;      // colptr[ncols]
  int64_t nnz() const { return colptr.empty() ? 0 : colptr.back(); }
};

// Builds a lower-triangular symmetric CSC matrix from triplets (i, j, v); entries
// with i < j are mirrored to (j, i); duplicates are summed. O(nnz + n).
LOCUS_API CscMatrix lower_from_triplets(int32_t n, const std::vector<int32_t>& ii, const std::vector<int32_t>& jj,
                                        const std::vector<double>& vv);

// y = A x for a lower-stored symmetric A.
LOCUS_API void symmetric_multiply(const CscMatrix& lower, const double* x, double* y);

// Linear combination a*A + b*B of two lower-stored matrices with the SAME pattern.
LOCUS_API CscMatrix combine_same_pattern(double a, const CscMatrix& A, double b, const CscMatrix& B);

}  // namespace locus
LOCUS_API_END
