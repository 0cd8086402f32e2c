// Where A's stored entries go in L's values (thesis §5.3; DESIGN.md "Numeric
// core" 2), grouped by supernode so that each supernode's task assembles its
// own block. Supernode s holds the entries whose column (the smaller factor
// index of the two) is one of s's, in ascending order of their index in A.
//
// A scatter over A's entries in their order, split into consecutive chunks
// that count their entries per supernode first (so each knows where its part
// of every group starts), then the positions in L per supernode: both as
// parallel oneTBB tasks of the caller's arena, the same result for every
// chunk count and thread count.
#pragma once
#include "locus/kernels/symbolic/symbolic_factor.hpp"

namespace locus {

// S has its supernodal structure and super_value_ptr; A is the lower CSC
// (original numbering). Sets a_super_ptr, a_src, a_dst; throws Error(Internal)
// if an entry of A has no place in L. chunks >= 1 costs chunks * ns * 8 bytes
// of counters; chunks == 1: no oneTBB algorithm runs.
void assembly_map(SymbolicFactor& S, const CscMatrix& A, int chunks);

// Frees the assembly map and the update lists (~16 bytes per entry of A), which
// only the numeric factorization reads, and the column etree and counts
// (`parent`, `col_count`, which only the analysis reads): for a factor that is
// computed once and then only solved with (and saved before). A later factorize / refactorize with S throws
// Error(BadUsage) instead of reading the missing map.
void release_assembly_map(SymbolicFactor& S);

}  // namespace locus
