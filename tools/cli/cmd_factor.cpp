// `locus factor MESH`: the numeric core end to end on one mesh operator
// (DESIGN.md "Numeric core" 1-5): METIS ordering, symbolic analysis,
// supernodal numeric factorization, a 1-lane and an 8-lane full solve, with
// per-phase medians over --repeat runs and the relative residual
// ||A x - b|| / ||b|| of a seeded random right-hand side (A applied with
// symmetric_multiply, independent of the factor) as the quality check.
// --load F replaces ordering, analysis and factorization by loading F (each
// repeat; order_s, symbolic_s, numeric_s are then 0 and factor_cache.load_s
// is the median load time); --save F writes the factor of the last repeat.
#include <algorithm>
#include <cmath>
#include <string>
#include <ostream>

#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

// Above this relative residual the solution has fewer than ~4 correct digits:
// the operator is numerically singular (e.g. a heat operator with t so large
// that M is lost next to tL), and `factor` reports a numerical failure (exit 4)
// instead of timings of a meaningless solve. Sane operators stay far below it:
// heat at t = h^2 gives ~1e-16, the regularized Laplacian (condition ~1e8 by
// construction) ~1e-10 on the sample meshes.
constexpr double kMaxResidual = 1e-4;

// max() that lets a NaN through, so that a NaN residual is never hidden.
double worst(double a, double b) { return (std::isnan(b) || b > a) ? b : a; }

struct FactorOptions {
  OperatorSpec op;
  int repeat = 1;
  FactorCacheOptions cache;
};

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

Repeats run_repeats(const FactorOptions& fo, const Mesh& mesh, const FactorRequest& req, const RightHandSides& rhs,
                    const RunContext& ctx) {
  Repeats out;
  std::vector<double> work;
  for (int r = 0; r < fo.repeat; ++r) {
    ctx.check_cancel();
    // Factored (or loaded with --load) every repeat; --save writes the last one.
    FactorCacheOptions cache = fo.cache;
    if (r + 1 < fo.repeat) cache.save.clear();
    const Factors Fs = factor_or_load(cache, mesh, std::span(&req, 1), ctx);
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
    Stopwatch sw;
    solve(F, out.x, work);
    out.solve_s.push_back(sw.seconds());

    out.x8 = rhs.b8;
    sw.restart();
    solve8(F, out.x8, work);
    out.solve8_s.push_back(sw.seconds());

    if (fo.repeat > 1)
      log("factor: repeat " + std::to_string(r + 1) + "/" + std::to_string(fo.repeat) + ": numeric " +
          format_number(out.numeric_s.back()) + " s");
  }
  return out;
}

// The residuals of the last repeat's solves, and the 8-lane path against the 1-lane one.
struct Accuracy {
  double residual = 0, residual8 = 0, lane0_vs_solve = 0;
};

Accuracy accuracy(const CscMatrix& A, const RightHandSides& rhs, const Repeats& rep) {
  const int32_t n = A.ncols;
  Accuracy a;
  a.residual = relative_residual(A, rep.x.data(), rhs.b.data());
  double xnorm = 0;
  std::vector<double> lane(static_cast<size_t>(n)), lane_b(static_cast<size_t>(n));
  for (int l = 0; l < kLanes; ++l) {
    for (int32_t i = 0; i < n; ++i) {
      lane[i] = rep.x8[static_cast<size_t>(i) * kLanes + l];
      lane_b[i] = rhs.b8[static_cast<size_t>(i) * kLanes + l];
    }
    a.residual8 = worst(a.residual8, relative_residual(A, lane.data(), lane_b.data()));
  }
  for (int32_t i = 0; i < n; ++i) {
    a.lane0_vs_solve = worst(a.lane0_vs_solve, std::abs(rep.x8[static_cast<size_t>(i) * kLanes] - rep.x[i]));
    xnorm = std::max(xnorm, std::abs(rep.x[i]));
  }
  if (xnorm > 0) a.lane0_vs_solve /= xnorm;
  return a;
}

Json factor_json(const CommonOptions& opt, const Input& in, const FactorOptions& fo, const BuiltOperator& op,
                 const Repeats& rep, const Accuracy& acc, double operator_s) {
  const SymbolicFactor& sym = *rep.sym;
  Json j{{"command", "factor"}, {"input", input_json(opt, in)}};
  j["operator"] = fo.op.kind;
  j["t"] = op.t;
  j["h"] = op.h;
  j["seed"] = opt.seed;
  j["threads"] = threads_used(opt);
  j["repeats"] = fo.repeat;
  j["n"] = op.A.ncols;
  j["nnz_A"] = op.A.nnz();
  j["nnz_L"] = sym.nnz_L;
  j["nnz_L_exact"] = sym.nnz_exact;
  j["supernodes"] = sym.ns;
  j["etree_height"] = sym.etree_height;
  j["super_etree_height"] = sym.super_etree_height;
  j["flops"] = sym.flops();
  j["order_s"] = median(rep.order_s);
  j["symbolic_s"] = median(rep.symbolic_s);
  j["numeric_s"] = median(rep.numeric_s);
  j["solve_s"] = median(rep.solve_s);
  j["solve8_s"] = median(rep.solve8_s);
  j["factor_cache"] = {{"loaded", fo.cache.load.empty() ? Json(nullptr) : Json(fo.cache.load)},
                       {"saved", fo.cache.save.empty() ? Json(nullptr) : Json(fo.cache.save)},
                       {"load_s", median(rep.load_s)},
                       {"save_s", rep.save_s.back()}};
  j["residual"] = acc.residual;
  j["residual8"] = acc.residual8;
  // max_i |x8[i, lane 0] - x[i]| / max_i |x[i]|: the 8-lane path must agree with the 1-lane one.
  j["solve8_lane0_vs_solve"] = acc.lane0_vs_solve;
  j["timings"] = timings(in, {{"operator_s", operator_s}});
  return j;
}

int run_factor(const CommonOptions& opt, const FactorOptions& fo, const RunContext& ctx) {
  validate_operator_spec(fo.op);  // bad --t is bad usage: say so before reading the file
  validate_factor_cache_options(fo.cache);
  Input in = load_input(opt, ctx);
  ctx.check_cancel();
  Stopwatch sw;
  const BuiltOperator op = build_operator(in.mesh, fo.op);
  const double operator_s = sw.seconds();
  const RightHandSides rhs = right_hand_sides(op.A.ncols, opt.seed);
  const FactorRequest req{fo.op.kind, op.t, &op.A};
  const Repeats rep = run_repeats(fo, in.mesh, req, rhs, ctx);
  const Accuracy acc = accuracy(op.A, rhs, rep);
  if (!(worst(acc.residual, acc.residual8) <= kMaxResidual)) {
    std::string what = fo.op.kind == "heat" ? "heat operator with t = " + format_number(op.t) : "regularized Laplacian";
    fail(ErrorCode::Numerical, "the solve is inaccurate: relative residual " + format_number(acc.residual) +
                                   " (worst of 8 lanes " + format_number(acc.residual8) + ") exceeds " +
                                   format_number(kMaxResidual) + "; the " + what +
                                   " is numerically singular or not finite");
  }
  const Json j = factor_json(opt, in, fo, op, rep, acc, operator_s);
  write_output_mesh(opt, output_faces(in), carried_attributes(in));
  const SymbolicFactor& sym = *rep.sym;
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": " << fo.op.kind << " operator";
    if (fo.op.kind == "heat") os << " (t = " << op.t << ", h = " << op.h << ")";
    os << "\n  n " << op.A.ncols << ", nnz(A) " << op.A.nnz() << ", nnz(L) " << sym.nnz_L << " (exact "
       << sym.nnz_exact << "), supernodes " << sym.ns << "\n  etree height " << sym.etree_height
       << ", supernodal etree height " << sym.super_etree_height << "\n  medians over " << fo.repeat
       << " run(s): order " << j["order_s"] << " s, symbolic " << j["symbolic_s"] << " s, numeric " << j["numeric_s"]
       << " s, solve " << j["solve_s"] << " s, solve8 " << j["solve8_s"] << " s\n"
       << (fo.cache.load.empty() ? std::string()
                                 : "  loaded from " + fo.cache.load + " in " + format_number(median(rep.load_s)) +
                                       " s\n")
       << "  residual " << acc.residual << ", 8-lane residual " << acc.residual8 << "\n";
  });
  return 0;
}

}  // namespace

void register_factor_command(CommandTable& table) {
  auto fo = std::make_shared<FactorOptions>();
  CLI::App* app = table.add("factor", "Order, analyze, factor and solve a mesh operator; timings and residual",
                            [fo](const CommonOptions& opt, const RunContext& ctx) { return run_factor(opt, *fo, ctx); });
  add_operator_options(app, fo->op);
  app->add_option("--repeat,--repeats", fo->repeat, "Repeat the pipeline R times and report medians (default 1)")
      ->check(CLI::Range(1, 1000));
  add_factor_cache_options(app, fo->cache);
}

}  // namespace locus::cli
