// `factor` as every front end runs it (engine/include/locus/engine/
// factor_request.hpp): the numeric core end to end on one cotan operator
// (DESIGN.md "Numeric core" 1-5). Each repeat orders, analyzes and factors
// the matrix (or loads the factor: order_s, symbolic_s, numeric_s are then 0
// and factor_cache.load_s is the median load time; save writes the last
// repeat's factor) and runs a 1-lane and an 8-lane full solve of a seeded
// random right-hand side; the residuals of the last repeat's solves, with A
// applied by symmetric_multiply (independent of the factor), are the quality
// check. The factor cache label is the matrix name with its t, so a heat
// factor of `locus factor` loads in voronoi or cvt with the same t.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>
#include <string>

#include "command_clock.hpp"
#include "locus/engine/factor_request.hpp"
#include "locus/engine/factor_store.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/solve/solve_accuracy.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/session.hpp"

namespace locus {
namespace {

using command_clock::median_of;
using command_clock::seconds;

// Above this relative residual the solution has fewer than ~4 correct digits:
// the operator is numerically singular (e.g. a heat operator with t so large
// that M is lost next to tL), and `factor` reports a numerical failure
// instead of timings of a meaningless solve. Sane operators stay far below it:
// heat at t = h^2 gives ~1e-16, the regularized Laplacian (condition ~1e8 by
// construction) ~1e-10 on the sample meshes.
constexpr double kMaxResidual = 1e-4;

// max() that lets a NaN through, so that a NaN residual is never hidden.
double worst(double a, double b) { return (std::isnan(b) || b > a) ? b : a; }

// Right-hand sides: lane 0 of the 8-lane block is the 1-lane b, so the two
// solves can be compared entry by entry.
struct RightHandSides {
  std::vector<double> b, b8;
};

RightHandSides right_hand_sides(int32_t n, uint64_t seed) {
  RightHandSides r;
  r.b = random_vector(static_cast<size_t>(n), seed);
  r.b8.resize(static_cast<size_t>(n) * kLanes);
  for (int lane = 0; lane < kLanes; ++lane) {
    const std::vector<double> col = lane == 0 ? r.b : random_vector(static_cast<size_t>(n), seed + lane);
    for (int32_t i = 0; i < n; ++i) r.b8[static_cast<size_t>(i) * kLanes + lane] = col[i];
  }
  return r;
}

// Per-phase times of every repeat, and the last repeat's solutions.
struct Repeats {
  std::vector<double> order_s, symbolic_s, numeric_s, solve_s, solve8_s, load_s, save_s;
  std::shared_ptr<const SymbolicFactor> sym;
  std::vector<double> x, x8;
};

Repeats run_repeats(const FactorCommandRequest& req, const Mesh& mesh, const FactorRequest& op,
                    const RightHandSides& rhs, const RunContext& ctx) {
  Repeats out;
  std::vector<double> work;
  for (int r = 0; r < req.repeat; ++r) {
    ctx.check_cancel();
    // Factored (or loaded) every repeat; save writes the last one.
    FactorCacheFiles cache{req.save, req.load};
    if (r + 1 < req.repeat) cache.save.clear();
    const Factors Fs = factor_or_load(cache, mesh, std::span(&op, 1), ctx);
    const NumericFactor& F = Fs.factors[0];
    out.sym = Fs.symbolic;
    out.order_s.push_back(Fs.order_s);
    out.symbolic_s.push_back(Fs.analyze_s);
    out.numeric_s.push_back(Fs.numeric_s);
    out.load_s.push_back(Fs.load_s);
    out.save_s.push_back(Fs.save_s);
    ctx.check_cancel();

    // Caller-owned workspace, sized outside the timers: the solves then do not allocate.
    work.resize(std::max(solve_work_size(F, 1), solve_work_size(F, kLanes)));
    out.x = rhs.b;
    auto t0 = std::chrono::steady_clock::now();
    solve(F, out.x, work);
    out.solve_s.push_back(seconds(t0));

    out.x8 = rhs.b8;
    t0 = std::chrono::steady_clock::now();
    solve8(F, out.x8, work);
    out.solve8_s.push_back(seconds(t0));

    if (req.repeat > 1)
      ctx.note("factor: repeat " + std::to_string(r + 1) + "/" + std::to_string(req.repeat) + ": numeric " +
               format_number(out.numeric_s.back()) + " s");
  }
  return out;
}

// The residuals of the last repeat's solves, and the 8-lane path against the 1-lane one.
void measure_accuracy(const CscMatrix& A, const RightHandSides& rhs, const Repeats& rep, FactorCommandReport& r) {
  const int32_t n = A.ncols;
  r.residual = relative_residual(A, rep.x.data(), rhs.b.data());
  double xnorm = 0;
  std::vector<double> lane(static_cast<size_t>(n)), lane_b(static_cast<size_t>(n));
  for (int l = 0; l < kLanes; ++l) {
    for (int32_t i = 0; i < n; ++i) {
      lane[i] = rep.x8[static_cast<size_t>(i) * kLanes + l];
      lane_b[i] = rhs.b8[static_cast<size_t>(i) * kLanes + l];
    }
    r.residual8 = worst(r.residual8, relative_residual(A, lane.data(), lane_b.data()));
  }
  for (int32_t i = 0; i < n; ++i) {
    r.lane0_vs_solve = worst(r.lane0_vs_solve, std::abs(rep.x8[static_cast<size_t>(i) * kLanes] - rep.x[i]));
    xnorm = std::max(xnorm, std::abs(rep.x[i]));
  }
  if (xnorm > 0) r.lane0_vs_solve /= xnorm;
}

void refuse_inaccurate(const FactorCommandReport& r) {
  if (worst(r.residual, r.residual8) <= kMaxResidual) return;
  const std::string what =
      r.matrix == "heat" ? "heat operator with t = " + format_number(r.t) : std::string("regularized Laplacian");
  fail(ErrorCode::Numerical, "the solve is inaccurate: relative residual " + format_number(r.residual) +
                                 " (worst of 8 lanes " + format_number(r.residual8) + ") exceeds " +
                                 format_number(kMaxResidual) + "; the " + what +
                                 " is numerically singular or not finite");
}

}  // namespace

void check_request(const FactorCommandRequest& req) {
  if (req.matrix != "heat" && req.matrix != "laplacian")
    fail(ErrorCode::BadUsage, "--matrix must be heat or laplacian (got '" + req.matrix + "')");
  if (req.matrix == "laplacian" && !req.t.empty()) fail(ErrorCode::BadUsage, "--t applies to --matrix heat only");
  if (!req.t.empty()) parse_heat_time(req.t, "--t");
  if (req.repeat < 1 || req.repeat > 1000)
    fail(ErrorCode::BadUsage, "--repeat must be in 1..1000 (got " + std::to_string(req.repeat) + ")");
  check_factor_cache_files({req.save, req.load});
}

FactorMatrix factor_matrix(const Mesh& m, const FactorCommandRequest& req) {
  check_request(req);
  const std::string where = m.source.empty() ? std::string("the mesh") : m.source;
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, where + " has no faces");
  // One edge incidence for the checks, h and the assembly (each would build its own).
  const EdgeIncidence inc = edge_incidence(m);
  check_requirements(m, MeshRequirements{}, analyze_mesh(m, inc));
  FactorMatrix op;
  op.h = mean_edge_length(m, inc.edges);
  if (!(op.h > 0) || !std::isfinite(op.h))
    fail(ErrorCode::BadInput, where + ": mean edge length is " + format_number(op.h) + ", cannot scale the operator");
  if (req.matrix == "laplacian") {
    op.A = regularized_laplacian(m, kLaplacianRegularization, &inc);
  } else {
    op.t = req.t.empty() ? op.h * op.h : parse_heat_time(req.t, "--t").resolve(op.h);
    op.A = heat_operator(m, op.t, &inc);
  }
  return op;
}

FactorCommandReport Session::factor(const FactorCommandRequest& req, const RunContext& ctx) const {
  check_request(req);
  const Mesh m = mesh();
  ctx.check_cancel();
  FactorCommandReport r;
  const auto t0 = std::chrono::steady_clock::now();
  const FactorMatrix op = factor_matrix(m, req);
  r.operator_s = seconds(t0);
  const RightHandSides rhs = right_hand_sides(op.A.ncols, req.seed);
  const FactorRequest label{req.matrix, op.t, &op.A};
  Repeats rep = run_repeats(req, m, label, rhs, ctx);
  r.matrix = req.matrix;
  r.t = op.t, r.h = op.h;
  measure_accuracy(op.A, rhs, rep, r);
  refuse_inaccurate(r);
  const SymbolicFactor& sym = *rep.sym;
  r.repeats = req.repeat;
  r.n = op.A.ncols;
  r.nnz_A = op.A.nnz();
  r.nnz_L = sym.nnz_L, r.nnz_L_exact = sym.nnz_exact;
  r.supernodes = sym.ns, r.etree_height = sym.etree_height, r.super_etree_height = sym.super_etree_height;
  r.flops = sym.flops();
  r.x = std::move(rep.x);
  r.order_s = median_of(rep.order_s), r.symbolic_s = median_of(rep.symbolic_s), r.numeric_s = median_of(rep.numeric_s);
  r.solve_s = median_of(rep.solve_s), r.solve8_s = median_of(rep.solve8_s);
  r.factor_cache = {req.load, req.save, median_of(rep.load_s), rep.save_s.back()};
  return r;
}

}  // namespace locus
