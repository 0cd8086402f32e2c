// The request and report of the `factor` command: the numeric core end to
// end on one mesh operator (DESIGN.md "Numeric core" 1-5): METIS ordering,
// symbolic analysis, supernodal numeric factorization, a 1-lane and an
// 8-lane full solve of a seeded random right-hand side, with per-phase
// medians over `repeat` runs and the relative residual ||A x - b|| / ||b||
// (A applied with symmetric_multiply, independent of the factor) as the
// quality check. As every front end runs it: the CLI (`locus factor`),
// locus::Session::factor, the C API (locus_factor_options in
// locus_commands.h) and Python (Session.factor_command). Each field is one
// option, named as the CLI's long option, with the CLI's default; the checks
// and the call sequence live once, in engine/src/session_factor_command.cpp.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/engine/geodesic_requests.hpp"
#include "locus/export.h"
#include "locus/mesh.hpp"
#include "locus/sparse_matrix.hpp"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API FactorCommandRequest {
  // heat: M - tL (cotan); laplacian: -L + eps M, eps = 1e-6 relative (the
  // CLI's --matrix; its older spelling --operator heat|laplacian is an alias).
  std::string matrix = "heat";
  std::string t;          // heat only: absolute ("1e-3") or a multiple of h^2 ("2h2"); "" = h2
  int32_t repeat = 1;     // 1..1000 runs of the whole sequence; the report gives medians
  std::string save, load; // factor cache files ("" = none); with load every repeat loads instead of factoring
  uint64_t seed = 1;      // of the random right-hand side (the CLI's --seed)
};

struct LOCUS_API FactorCommandReport {
  std::string matrix;
  double t = 0;           // the diffusion time used (0 for the Laplacian)
  double h = 0;           // mean edge length
  int32_t repeats = 0;
  int32_t n = 0;          // rows of A
  int64_t nnz_A = 0;      // stored entries of the lower triangle
  int64_t nnz_L = 0, nnz_L_exact = 0;  // of the supernodal factor (with and without amalgamation zeros)
  int32_t supernodes = 0, etree_height = 0, super_etree_height = 0;
  int64_t flops = 0;      // of one numeric factorization
  std::vector<double> x;  // the last repeat's 1-lane solution
  // ||A x - b|| / ||b|| of the 1-lane solve, the worst over the 8 lanes, and
  // max_i |x8[i, lane 0] - x[i]| / max_i |x[i]| (the 8-lane path against the 1-lane one).
  double residual = 0, residual8 = 0, lane0_vs_solve = 0;
  // Seconds: building A once, then the medians over the repeats (0 when loaded).
  double operator_s = 0, order_s = 0, symbolic_s = 0, numeric_s = 0, solve_s = 0, solve8_s = 0;
  FactorCacheReport factor_cache;  // load_s: median over the repeats; save_s: the last repeat's
};

// Argument checks that need no mesh: Error(BadUsage).
LOCUS_API void check_request(const FactorCommandRequest& req);

// The request's matrix on `mesh`, lower CSC in the mesh's vertex order, with
// the t it used (0 for the Laplacian) and the mean edge length h. The mesh
// must suit the cotan operators (triangles, manifold, no degenerate faces, no
// unreferenced vertices: Error(BadInput) naming the first offender).
struct LOCUS_API FactorMatrix {
  CscMatrix A;
  double t = 0, h = 0;
};
LOCUS_API FactorMatrix factor_matrix(const Mesh& mesh, const FactorCommandRequest& req);

}  // namespace locus
LOCUS_API_END
