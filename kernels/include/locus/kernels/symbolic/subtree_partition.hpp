// Independent subtrees of a postordered elimination tree (thesis §4.2: columns
// in disjoint subtrees are eliminated independently).
//
// The symbolic analysis walks the etree bottom-up (column counts, supernode row
// structures). Disjoint subtrees share no state below their roots, so they can
// be processed as parallel tasks, and the nodes above them ("top" nodes, the
// upper separators of a nested dissection) after. In a postordered forest
// (parent[j] > j, every subtree the contiguous range ending at its root) a set
// of whole subtrees next to each other is one contiguous range: a piece.
#pragma once
#include <cstdint>
#include <span>

#include "locus/core/host_allocator.hpp"

namespace locus {

struct SubtreePartition {
  // Piece q holds the nodes [piece_begin[q], piece_end[q]), ascending and
  // disjoint: whole subtrees whose roots' parents are top nodes (or -1).
  HostVector<int32_t> piece_begin, piece_end;
  // Every node in no piece, ascending: all its ancestors are top nodes too.
  HostVector<int32_t> top;
  int32_t num_pieces() const { return static_cast<int32_t>(piece_begin.size()); }
};

// weight[j] >= 0 is node j's own work. A node whose subtree weighs more than
// max_piece_weight is a top node; the maximal subtrees below are pieces, and
// neighbouring ones are joined while the joined weight stays within the bound
// (fewer, larger tasks). max_piece_weight >= the total weight: one piece, no
// top node. Depends on parent, weight and the bound only (never on threads
// running), so a caller's results can be made independent of scheduling.
SubtreePartition subtree_partition(std::span<const int32_t> parent, HostVector<int64_t> weight,
                                   int64_t max_piece_weight);

}  // namespace locus
