// Where A's stored entries go in L's values (thesis §5.3; DESIGN.md "Numeric
// core" 2), grouped by supernode so that each supernode's task assembles its
// own block. Supernode s holds the entries whose column (the smaller factor
// index of the two) is one of s's, in ascending order of their index in A;
// each supernode's group is built on its own, so the groups are filled as
// parallel oneTBB tasks.
#pragma once
#include "locus/kernels/symbolic/permuted_graph.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"

namespace locus {

// S has its supernodal structure and super_value_ptr; A is the lower CSC
// (original numbering) and `above` its Above half graph in S's numbering, with
// src. Sets a_super_ptr, a_src, a_dst; throws Error(Internal) if an entry of A
// has no place in L.
void assembly_map(SymbolicFactor& S, const CscMatrix& A, const HalfGraph& above);

}  // namespace locus
