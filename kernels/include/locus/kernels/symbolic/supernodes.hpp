// Supernode partition of a postordered elimination tree (thesis §5.3):
// fundamental supernodes (chains of columns with nested structure), then
// relaxed amalgamation that merges a supernode into its parent when the
// explicit zeros this adds stay small, trading a little fill for BLAS-3 blocks.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"

#include "locus/kernels/symbolic/symbolic_factor.hpp"

namespace locus {

// parent[] and col_count[] in a postordered numbering (every subtree contiguous).
// Returns super_first_col (ns + 1 entries).
HostVector<int32_t> relaxed_supernodes(std::span<const int32_t> parent, std::span<const int32_t> col_count,
                                        const SymbolicOptions& opt);

}  // namespace locus
