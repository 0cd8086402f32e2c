// One supernode of a numeric factor as the triangular solves read it: first
// column f, k columns, m rows (the first k are its own columns), the row list
// and the dense column-major block L (ld = m). Internal to kernels/src/solve.
#pragma once
#include <cstdint>

#include "locus/kernels/factor/supernodal_factor.hpp"

namespace locus {

struct SupernodeBlock {
  int32_t f, k, m;
  const int32_t* rows;
  const double* L;
};

inline SupernodeBlock supernode_block(const NumericFactor& F, int32_t s) {
  const SymbolicFactor& S = *F.symbolic;
  return {S.super_first_col[s], S.ncols(s), S.nrows(s), S.super_rows.data() + S.super_row_ptr[s], F.block(s)};
}

}  // namespace locus
