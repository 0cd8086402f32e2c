// The contenders of `locus-bench factor` (bench_factor.cpp describes the
// measurement): locus, Eigen's SimplicialLLT with METIS ordering and CHOLMOD,
// each run once per repeat on the same matrix and right-hand sides.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/kernels/order/ordering.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::bench::factor {

// Per-peer samples (one entry per repeat) and final figures.
struct PeerRun {
  std::vector<double> analyze_s, order_s, symbolic_s, factor_first_s, factor_repeat_s, solve_s, solve8_s;
  std::vector<double> first_answer_s;  // operator + analyze + first factorization + one solve, per repeat
  double nnz_L = 0;         // entries of the exact (pure) factor L
  double nnz_L_stored = 0;  // entries stored, including supernodal amalgamation zeros
  std::vector<double> x;    // solution of the 1-lane system
  std::vector<double> x8;   // solutions of the 8-lane system, column-major n x 8
  cli::Json extra = cli::Json::object();

  void close_repeat(double operator_s) {
    first_answer_s.push_back(operator_s + analyze_s.back() + factor_first_s.back() + solve_s.back());
  }
  cli::Json medians() const {
    cli::Json j{{"analyze_s", cli::median(analyze_s)}};
    if (!order_s.empty()) j["order_s"] = cli::median(order_s);
    if (!symbolic_s.empty()) j["symbolic_s"] = cli::median(symbolic_s);
    j["factor_first_s"] = cli::median(factor_first_s);
    j["factor_repeat_s"] = cli::median(factor_repeat_s);
    j["solve_s"] = cli::median(solve_s);
    j["solve8_s"] = cli::median(solve8_s);
    j["first_answer_s"] = cli::median(first_answer_s);
    j["nnz_L"] = nnz_L;
    j["nnz_L_stored"] = nnz_L_stored;
    j.update(extra);
    return j;
  }
};

// The right-hand sides: b, and an n x 8 block (column-major) whose first column is b.
struct Rhs {
  int32_t n = 0;
  std::vector<double> b, b8;
};

// Relative 2-norm distance of a from ref (absolute when ref is zero).
double rel_diff(const std::vector<double>& a, const std::vector<double>& ref);

// One repeat of each contender: analyze, factor twice, solve 1 and 8 lanes.
void run_locus(const CscMatrix& A, const OrderingOptions& oo, const Rhs& rhs, const RunContext& ctx, PeerRun& out);
void run_eigen(const CscMatrix& A, const Rhs& rhs, PeerRun& out);
#ifdef LOCUS_HAVE_CHOLMOD
// ordering: "default" (CHOLMOD's own choice), "metis" or "amd".
void run_cholmod(const std::string& ordering, const CscMatrix& A, const Rhs& rhs, PeerRun& out);
#endif

}  // namespace locus::bench::factor
