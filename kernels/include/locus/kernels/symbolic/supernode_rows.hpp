// Row structures of the supernodes (thesis §5.3): the rows of supernode s are
// its own columns, then the rows below them of A's columns in s and of s's
// children, ascending. The count is known beforehand: the columns of a
// relaxed supernode form an etree path, so its rows below are those of its
// last column, col_count - 1 of them; every supernode's rows therefore have a
// fixed place in super_rows and disjoint subtrees fill theirs as parallel tasks.
#pragma once
#include <cstdint>
#include <span>

#include "locus/kernels/symbolic/subtree_partition.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"

namespace locus {

// S has n, ns, super_first_col, super_parent and col_count; sets super_row_ptr
// and super_rows. ptr/idx: the neighbours above each column (factor numbering).
// `part` partitions the supernodal etree: its pieces run as oneTBB tasks of the
// caller's arena, then the top supernodes. Same result for every partition.
void supernode_rows(SymbolicFactor& S, std::span<const int64_t> ptr, std::span<const int32_t> idx,
                    const SubtreePartition& part);

}  // namespace locus
