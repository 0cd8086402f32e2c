// Selected inversion: the entries of Z = A^{-1} on the pattern of L (Takahashi
// et al. 1973; supernodal form as in Lin et al.'s SelInv), beyond the thesis
// (DESIGN.md "Numeric core" 7). diag(A^{-1}) for every vertex — the
// auto-diffusion function of thesis §4.6 at all vertices — costs a small
// multiple of one factorization instead of n solves.
//
// For a supernode with columns J, rows below R, U = L21 L11^{-1}:
//   Z_RJ = -Z_RR U,   Z_JJ = (L11 L11^T)^{-1} - U^T Z_RJ,
// where Z_RR lies on the pattern of L (the rows of a column form a clique) and
// belongs to ancestors, so supernodes are processed root first.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "locus/kernels/factor/supernodal_factor.hpp"

namespace locus {

struct SelectedInverse {
  std::shared_ptr<const SymbolicFactor> symbolic;
  // Same layout as NumericFactor::values: Z on the lower pattern of L.
  std::vector<double, DefaultInitAllocator<double>> values;
};

SelectedInverse selected_inversion(const NumericFactor& f, const RunContext& ctx = {});
// (A^{-1})_ii for every i, original numbering.
std::vector<double> inverse_diagonal(const SelectedInverse& z);
// (A^{-1})_ij for original ids i, j whose factor entry is on the pattern of L; throws BadUsage otherwise.
double inverse_entry(const SelectedInverse& z, int32_t i, int32_t j);

}  // namespace locus
