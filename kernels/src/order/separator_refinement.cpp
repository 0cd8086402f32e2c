// FM refinement of vertex separators (kernels/include/locus/kernels/order/separator_refinement.hpp).
#include "locus/kernels/order/separator_refinement.hpp"

#include <algorithm>
#include <cstdlib>
#include <vector>
#include <utility>

namespace locus {

namespace {

class Refiner {
 public:
  Refiner(const AdjacencyGraph& g, HostVector<int8_t>& part, const SeparatorRefinementOptions& opt,
          SeparatorRefinementWorkspace& ws)
      : g_(g), part_(part), opt_(opt), ws_(ws), gain_(ws.gain), stamp_(ws.stamp), joined_(ws.joined),
        buckets_(ws.buckets), sep_(ws.sep), moved_(ws.moved), pulled_(ws.pulled), pulled_begin_(ws.pulled_begin) {
    const int32_t n = g.n();
    // The workspace's marks only grow (stamps and move numbers are never
    // reused), so a call costs nothing per vertex it never touches.
    if (gain_.size() < static_cast<size_t>(n)) {
      gain_.resize(static_cast<size_t>(n));
      stamp_.resize(static_cast<size_t>(n), -1);
      joined_.resize(static_cast<size_t>(n), -1);
    }
    first_pass_ = ws.next_pass;
    int32_t max_degree = 0;
    for (int32_t v = 0; v < n; ++v) max_degree = std::max(max_degree, g.xadj[v + 1] - g.xadj[v]);
    min_gain_ = 1 - max_degree;
    for (auto& b : buckets_) b.clear();
    if (buckets_.size() < static_cast<size_t>(max_degree) + 1) buckets_.resize(static_cast<size_t>(max_degree) + 1);
    sep_.clear();
    int32_t side0 = 0;
    for (int32_t v = 0; v < n; ++v) {
      const int8_t s = part_[v];
      side0 += s == 0;
      if (s == 2) sep_.push_back(v);
    }
    pw_[0] = side0;
    pw_[2] = static_cast<int32_t>(sep_.size());
    pw_[1] = n - side0 - pw_[2];
  }

  ~Refiner() { ws_.next_pass = first_pass_ + opt_.passes; }

  int32_t run() {
    int bad_passes = 0;
    int8_t to = pw_[0] <= pw_[1] ? 0 : 1;  // first toward the lighter side: that also evens the balance
    for (int pass = 0; pass < opt_.passes && bad_passes < 2 && pw_[2] > 0; ++pass, to = static_cast<int8_t>(1 - to))
      bad_passes = one_pass(first_pass_ + pass, to) ? 0 : bad_passes + 1;
    return pw_[2];
  }

 private:
  // The move queue: best gain first, ties last in first out. LIFO keeps a
  // pass working where it just moved (the separator's front), which gave
  // 1-2% less fill than ties by vertex index (docs/ordering.md). Gains are
  // small integers (1 - neighbors on one side), so one stack per gain
  // (a bucket queue) gives that order in O(1) per entry: the same moves as
  // a binary heap of (gain, push count, vertex), cheaper.
  void enqueue(int32_t gain, int32_t v) {
    const int32_t b = gain - min_gain_;
    buckets_[b].push_back(v);
    top_ = std::max(top_, b);
  }

  // The best entry (gain, vertex) into *gain, *v; false when none is left.
  bool dequeue(int32_t* gain, int32_t* v) {
    while (top_ >= 0 && buckets_[top_].empty()) --top_;
    if (top_ < 0) return false;
    *v = buckets_[top_].back();
    buckets_[top_].pop_back();
    *gain = top_ + min_gain_;
    return true;
  }

  void clear_queue() {
    for (; top_ >= 0; --top_) buckets_[top_].clear();
  }

  bool balanced(int32_t a, int32_t b) const { return std::max(a, b) <= opt_.max_imbalance * 0.5 * (a + b); }

  int32_t neighbors_in(int32_t v, int8_t side) const {
    int32_t k = 0;
    for (int32_t p = g_.xadj[v]; p < g_.xadj[v + 1]; ++p) k += part_[g_.adj[p]] == side;
    return k;
  }

  void push(int32_t v, int8_t other, int64_t pass) {
    if (stamp_[v] == pass) return;
    gain_[v] = 1 - neighbors_in(v, other);
    enqueue(gain_[v], v);
  }

  // One pass toward side `to`; true when it shrank the separator.
  bool one_pass(int64_t pass, int8_t to) {
    const int8_t other = static_cast<int8_t>(1 - to);
    clear_queue();
    for (const int32_t v : sep_) push(v, other, pass);
    const int32_t start_sep = pw_[2];
    int32_t best_sep = pw_[2], best_diff = std::abs(pw_[0] - pw_[1]);
    bool best_balanced = balanced(pw_[0], pw_[1]);
    size_t best_len = 0;
    // Hill climbing: `patience` moves past the best state of the pass, or
    // `stretch` times as many while the separator stays within 10% of it
    // (the longer climbs find the shorter separators: docs/ordering.md).
    const int32_t patience = std::clamp(2 * start_sep, 20, opt_.patience);
    const int32_t stretched = opt_.stretch * patience;
    int32_t since_best = 0;
    moved_.clear();
    pulled_.clear();
    pulled_begin_.clear();
    int32_t gn = 0, v = 0;
    while (since_best <= stretched && (since_best <= patience || 10 * pw_[2] <= 11 * best_sep) && dequeue(&gn, &v)) {
      if (part_[v] != 2 || stamp_[v] == pass || gain_[v] != gn) continue;  // stale entry
      const int32_t k = 1 - gn;                                            // neighbors pulled from `other`
      stamp_[v] = pass;  // moved or refused: not again in this pass
      if (!balanced(pw_[to] + 1, pw_[other] - k) && pw_[to] + 1 > pw_[other] - k) continue;
      part_[v] = to;
      moved_.push_back(v);
      pulled_begin_.push_back(static_cast<int32_t>(pulled_.size()));
      for (int32_t p = g_.xadj[v]; p < g_.xadj[v + 1]; ++p)
        if (const int32_t w = g_.adj[p]; part_[w] == other) { part_[w] = 2; pulled_.push_back(w); }
      pw_[to] += 1;
      pw_[other] -= k;
      pw_[2] += k - 1;
      // Gains that changed: the vertices that entered the separator (counted
      // once), and the separator vertices next to them, which lost one
      // neighbor on `other` per pulled neighbor: +1 each, no recount. Within
      // a pass vertices only leave `other`, so every gain stays exact, and
      // the entries come in the order a recount of each would push them
      // (same ties, same moves as recounting every neighbor's neighbors).
      const size_t b = static_cast<size_t>(pulled_begin_.back());
      const int64_t move_id = ++ws_.move_id;
      for (size_t q = b; q < pulled_.size(); ++q) {
        const int32_t w = pulled_[q];
        joined_[w] = move_id;
        gain_[w] = 1 - neighbors_in(w, other);
      }
      for (size_t q = b; q < pulled_.size(); ++q) {
        const int32_t w = pulled_[q];
        enqueue(gain_[w], w);
        for (int32_t p = g_.xadj[w]; p < g_.xadj[w + 1]; ++p)
          if (const int32_t x = g_.adj[p]; part_[x] == 2 && stamp_[x] != pass) {
            if (joined_[x] != move_id) ++gain_[x];
            enqueue(gain_[x], x);
          }
      }
      const bool bal = balanced(pw_[0], pw_[1]);
      const int32_t diff = std::abs(pw_[0] - pw_[1]);
      if ((bal && !best_balanced) || (bal == best_balanced && (pw_[2] < best_sep || (pw_[2] == best_sep && diff < best_diff)))) {
        best_sep = pw_[2];
        best_diff = diff;
        best_balanced = bal;
        best_len = moved_.size();
        since_best = 0;
      } else {
        ++since_best;
      }
    }
    while (moved_.size() > best_len) {  // roll back to the best state of the pass
      const int32_t v = moved_.back();
      const size_t b = static_cast<size_t>(pulled_begin_.back());
      for (size_t q = b; q < pulled_.size(); ++q) part_[pulled_[q]] = other;
      const int32_t k = static_cast<int32_t>(pulled_.size() - b);
      pulled_.resize(b);
      part_[v] = 2;
      pw_[to] -= 1;
      pw_[other] += k;
      pw_[2] -= k - 1;
      moved_.pop_back();
      pulled_begin_.pop_back();
    }
    // The separator now: the old one without the moved vertices, and the pulled ones kept.
    size_t kept = 0;
    for (const int32_t v : sep_)
      if (part_[v] == 2) sep_[kept++] = v;
    sep_.resize(kept);
    for (const int32_t v : pulled_)
      if (part_[v] == 2) sep_.push_back(v);
    return pw_[2] < start_sep;
  }

  const AdjacencyGraph& g_;
  HostVector<int8_t>& part_;
  const SeparatorRefinementOptions& opt_;
  SeparatorRefinementWorkspace& ws_;
  int64_t first_pass_ = 0;     // this call's passes are first_pass_ + 0, 1, ...
  HostVector<int32_t>& gain_;  // 1 - neighbors on the pass' `other` side (separator vertices)
  HostVector<int64_t>& stamp_;  // pass in which the vertex left the separator (locked)
  HostVector<int64_t>& joined_;  // move that pulled the vertex into the separator
  int32_t pw_[3] = {0, 0, 0};   // vertices per side and in the separator
  std::vector<HostVector<int32_t>>& buckets_;  // entries of gain min_gain_ + b, latest last (some stale)
  int32_t min_gain_ = 0;
  int32_t top_ = -1;  // no entries above this bucket
  HostVector<int32_t>& sep_;  // the separator's vertices at the start of a pass
  HostVector<int32_t>& moved_;
  HostVector<int32_t>& pulled_;
  HostVector<int32_t>& pulled_begin_;
};

}  // namespace

int32_t refine_vertex_separator(const AdjacencyGraph& g, HostVector<int8_t>& part,
                                const SeparatorRefinementOptions& opt, SeparatorRefinementWorkspace* ws) {
  if (ws) return Refiner(g, part, opt, *ws).run();
  SeparatorRefinementWorkspace own;
  return Refiner(g, part, opt, own).run();
}

}  // namespace locus
