// Fundamental supernodes and relaxed amalgamation (kernels/include/locus/kernels/symbolic/supernodes.hpp).
//
// Columns j and j+1 belong to one fundamental supernode when j+1 is j's parent,
// j is its only child, and their structures nest (count(j) = count(j+1) + 1).
// Amalgamation then walks supernodes in postorder and merges a supernode into
// its parent when the parent immediately follows it (it is the parent's last
// child, so the merged columns stay contiguous) and the merged block is small
// or adds few explicit zeros; thresholds are CHOLMOD-like and tunable.
#include "locus/kernels/symbolic/supernodes.hpp"
#include "locus/core/host_allocator.hpp"

#include <algorithm>

namespace locus {

HostVector<int32_t> relaxed_supernodes(std::span<const int32_t> parent, std::span<const int32_t> col_count,
                                        const SymbolicOptions& opt) {
  const int32_t n = static_cast<int32_t>(parent.size());
  HostVector<int32_t> nchild(n, 0);
  for (int32_t j = 0; j < n; ++j)
    if (parent[j] >= 0) ++nchild[parent[j]];

  // Fundamental supernodes.
  HostVector<int32_t> fs;  // first columns
  for (int32_t j = 0; j < n; ++j) {
    const bool continues = j > 0 && parent[j - 1] == j && nchild[j] == 1 && col_count[j - 1] == col_count[j] + 1;
    if (!continues) fs.push_back(j);
  }
  fs.push_back(n);
  const int32_t nf = static_cast<int32_t>(fs.size()) - 1;
  if (nf <= 1) return fs;

  // Per fundamental supernode: parent supernode, rows (count of first column),
  // and true nonzeros of its trapezoid.
  HostVector<int32_t> col_super(n);
  for (int32_t s = 0; s < nf; ++s)
    for (int32_t j = fs[s]; j < fs[s + 1]; ++j) col_super[j] = s;
  HostVector<int32_t> sparent(nf), ncols(nf), nrows(nf);
  HostVector<int64_t> nnz(nf, 0);
  for (int32_t s = 0; s < nf; ++s) {
    const int32_t last = fs[s + 1] - 1;
    sparent[s] = parent[last] < 0 ? -1 : col_super[parent[last]];
    ncols[s] = fs[s + 1] - fs[s];
    nrows[s] = col_count[fs[s]];
    for (int32_t j = fs[s]; j < fs[s + 1]; ++j) nnz[s] += col_count[j];
  }

  // Merge bottom-up. `merged_into_next[s]` marks s joined with s + 1.
  // A run of merged supernodes is tracked by its accumulated width, rows, nnz.
  HostVector<char> merge_next(nf, 0);
  int32_t run_cols = ncols[0], run_rows = nrows[0];
  int64_t run_nnz = nnz[0];
  for (int32_t s = 0; s + 1 < nf; ++s) {
    const int32_t p = s + 1;
    bool merge = false;
    if (sparent[s] == p) {
      const int64_t mc = static_cast<int64_t>(run_cols) + ncols[p];
      const int64_t mr = static_cast<int64_t>(run_cols) + nrows[p];  // child's columns + parent's rows
      // Entries of the merged lower trapezoid (mr rows, mc columns).
      const int64_t total = mc * mr - mc * (mc - 1) / 2;
      const double zeros = static_cast<double>(total - (run_nnz + nnz[p])) / static_cast<double>(total);
      if (mc <= opt.max_super_cols) {
        if (mc <= opt.relax_cols_small) merge = true;
        else if (mc <= opt.relax_cols_medium) merge = zeros < opt.relax_zeros_medium;
        else if (mc <= opt.relax_cols_large) merge = zeros < opt.relax_zeros_large;
        else merge = zeros < opt.relax_zeros_huge;
      }
      if (merge) {
        merge_next[s] = 1;
        run_nnz = total;  // the merged block stores its zeros: count them as entries
        run_cols = static_cast<int32_t>(mc);
        run_rows = static_cast<int32_t>(mr);
      }
    }
    if (!merge) {
      run_cols = ncols[p];
      run_rows = nrows[p];
      run_nnz = nnz[p];
    }
  }
  (void)run_rows;
  HostVector<int32_t> out;
  out.push_back(0);
  for (int32_t s = 0; s < nf; ++s)
    if (!merge_next[s]) out.push_back(fs[s + 1]);
  return out;
}

}  // namespace locus
