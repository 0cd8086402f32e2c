// The supernodal structure of L restricted to a vertex set I, the first step of
// the factor-once update (thesis §5.5): every global supernode keeps its
// columns and rows in I, and what remains is a closed supernodal structure that
// holds the factor of A_II. Internal to kernels/src/update (factor_update.cpp
// and its steps); the passes and their costs are described there.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/kernels/symbolic/symbolic_factor.hpp"

namespace locus::update_detail {

// The restricted supernodal structure, with the positions of its rows and
// columns inside the global supernodes (for copying values).
struct Restricted {
  int32_t ns = 0;
  std::vector<int32_t> gsuper;      // ns: global supernode it comes from
  std::vector<int32_t> first_col;   // ns + 1
  std::vector<int32_t> gcol;        // m: global factor column of each restricted column
  std::vector<int32_t> colpos;      // m: offset of that column inside its global supernode
  std::vector<int64_t> row_ptr;     // ns + 1
  std::vector<int32_t> rows;        // restricted column ids, ascending per supernode
  std::vector<int32_t> rowpos;      // position of each row in the global supernode's row list
  std::vector<int32_t> parent;      // ns
};

// A structure pass is split over two threads only when it handles at least
// this many rows: below, waking the second thread could cost what the half
// saves (not tuned; docs/factor_update.md).
constexpr int64_t kSplitRows = int64_t{1} << 14;

// The restricted supernodes of the global supernodes holding gcol (I's factor
// columns, ascending), in L's order; col_new maps a factor column to its
// restricted column (-1 outside I). With two_threads, a large structure is
// restricted in two halves side by side (same result).
Restricted restrict_structure(const SymbolicFactor& S, const std::vector<int32_t>& col_new, std::vector<int32_t> gcol,
                              bool two_threads);

// Renumbers the restricted supernodes in postorder of their tree (children in
// ascending order, so an order that is already a postorder is kept). Needed
// when I splits a global subtree: a restricted node can then become a root (or
// hang elsewhere) in the middle of another node's range, and the parallel
// factorization relies on contiguous subtrees.
// Returns false when the order was a postorder already (R unchanged).
bool postorder_in_place(Restricted& R, bool two_threads);

// The parts of the restricted symbolic factor that do not involve A (what
// complete_symbolic derives, in single passes): value offsets, column etree and
// counts, heights, workspace sizes and the update lists (for each s, the
// supernodes d < s with a row in s's columns, ascending).
void complete_structure(SymbolicFactor& S, bool two_threads);

}  // namespace locus::update_detail
