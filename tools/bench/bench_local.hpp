// `locus-bench local`: the parts its sections share (bench_local.cpp, the
// heat values of local_heat_values.cpp, the patch maps of local_patches.cpp).
#pragma once
#include <cstdint>
#include <string>

#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/mesh.hpp"
#include "locus/sparse_matrix.hpp"
#include "tools/bench/bench_commands.hpp"

namespace locus::bench::local {

struct Options {
  std::string t_text = "1h2";
  int pairs = 100;
  int adf_sample = 100;
  int adf_subset_limit = 300000;
  std::string patch_sizes = "2000,10000,30000,50000";
  int patch_centers = 5;
  bool skip_adf = false, skip_patch = false;
  // The heat section's ordering: auto (the library's default), or metis
  // (METIS_NodeND, the former default), nd, amd: the local solves
  // of two orderings compared in one binary.
  std::string ordering = "auto";
};

// peer / mine, 0 when mine is not positive: > 1 when locus is faster.
inline double ratio(double peer, double mine) { return mine > 0 ? peer / mine : 0.0; }

// Sections 1 and 2: heat values (pairs, lanes, single entries) and
// auto-diffusion at all vertices, on the heat operator M - tL.
cli::Json bench_pairs(const Mesh& m, double t, const Options& bo, uint64_t seed, const RunContext& ctx);
// Section 3: patch parameterization; F is the factor of m's regularized Laplacian.
cli::Json bench_patches(const Mesh& m, const NumericFactor& F, const Options& bo, uint64_t seed, const RunContext& ctx);
// Section 4: circle-boundary patch maps, K the regularized Laplacian and F its factor.
cli::Json bench_circle_patches(const Mesh& m, const CscMatrix& K, const NumericFactor& F, const Options& bo,
                               uint64_t seed, const RunContext& ctx);

}  // namespace locus::bench::local
