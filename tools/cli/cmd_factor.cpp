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

int run_factor(const CommonOptions& opt, const FactorOptions& fo, const RunContext& ctx) {
  validate_operator_spec(fo.op);  // bad --t is bad usage: say so before reading the file
  validate_factor_cache_options(fo.cache);
  Input in = load_input(opt, ctx);
  ctx.check_cancel();
  Stopwatch sw;
  const BuiltOperator op = build_operator(in.mesh, fo.op);
  const double operator_s = sw.seconds();
  const CscMatrix& A = op.A;
  const int32_t n = A.ncols;

  // Right-hand sides: lane 0 of the 8-lane block is the 1-lane b, so the two
  // solves can be compared entry by entry.
  const std::vector<double> b = random_vector(static_cast<size_t>(n), opt.seed);
  std::vector<double> b8(static_cast<size_t>(n) * kLanes);
  for (int lane = 0; lane < kLanes; ++lane) {
    const std::vector<double> col = lane == 0 ? b : random_vector(static_cast<size_t>(n), opt.seed + lane);
    for (int32_t i = 0; i < n; ++i) b8[static_cast<size_t>(i) * kLanes + lane] = col[i];
  }
  std::vector<double> x(b.size()), x8(b8.size()), work;

  std::vector<double> order_s, symbolic_s, numeric_s, solve_s, solve8_s, load_s, save_s;
  std::shared_ptr<const SymbolicFactor> sym;
  const FactorRequest req{fo.op.kind, op.t, &A};
  for (int r = 0; r < fo.repeat; ++r) {
    ctx.check_cancel();
    // Factored (or loaded with --load) every repeat; --save writes the last one.
    FactorCacheOptions cache = fo.cache;
    if (r + 1 < fo.repeat) cache.save.clear();
    const Factors Fs = factor_or_load(cache, in.mesh, std::span(&req, 1), ctx);
    const NumericFactor& F = Fs.factors[0];
    sym = Fs.symbolic;
    order_s.push_back(Fs.order_s);
    symbolic_s.push_back(Fs.analyze_s);
    numeric_s.push_back(Fs.numeric_s);
    load_s.push_back(Fs.load_s);
    save_s.push_back(Fs.save_s);
    ctx.check_cancel();

    // Caller-owned workspace, sized outside the timers: the solves then do not allocate.
    work.resize(std::max(solve_work_size(F, 1), solve_work_size(F, kLanes)));
    x = b;
    sw.restart();
    solve(F, x, work);
    solve_s.push_back(sw.seconds());

    x8 = b8;
    sw.restart();
    solve8(F, x8, work);
    solve8_s.push_back(sw.seconds());

    if (fo.repeat > 1)
      log("factor: repeat " + std::to_string(r + 1) + "/" + std::to_string(fo.repeat) + ": numeric " +
          format_number(numeric_s.back()) + " s");
  }

  const double residual = relative_residual(A, x.data(), b.data());
  double residual8 = 0, lane0_vs_solve = 0, xnorm = 0;
  std::vector<double> lane(static_cast<size_t>(n)), lane_b(static_cast<size_t>(n));
  for (int l = 0; l < kLanes; ++l) {
    for (int32_t i = 0; i < n; ++i) {
      lane[i] = x8[static_cast<size_t>(i) * kLanes + l];
      lane_b[i] = b8[static_cast<size_t>(i) * kLanes + l];
    }
    residual8 = worst(residual8, relative_residual(A, lane.data(), lane_b.data()));
  }
  for (int32_t i = 0; i < n; ++i) {
    lane0_vs_solve = worst(lane0_vs_solve, std::abs(x8[static_cast<size_t>(i) * kLanes] - x[i]));
    xnorm = std::max(xnorm, std::abs(x[i]));
  }
  if (xnorm > 0) lane0_vs_solve /= xnorm;
  if (!(worst(residual, residual8) <= kMaxResidual)) {
    std::string what = fo.op.kind == "heat" ? "heat operator with t = " + format_number(op.t) : "regularized Laplacian";
    fail(ErrorCode::Numerical, "the solve is inaccurate: relative residual " + format_number(residual) +
                                   " (worst of 8 lanes " + format_number(residual8) + ") exceeds " +
                                   format_number(kMaxResidual) + "; the " + what +
                                   " is numerically singular or not finite");
  }

  Json j{{"command", "factor"}, {"input", input_json(opt, in)}};
  j["operator"] = fo.op.kind;
  j["t"] = op.t;
  j["h"] = op.h;
  j["seed"] = opt.seed;
  j["threads"] = threads_used(opt);
  j["repeats"] = fo.repeat;
  j["n"] = n;
  j["nnz_A"] = A.nnz();
  j["nnz_L"] = sym->nnz_L;
  j["nnz_L_exact"] = sym->nnz_exact;
  j["supernodes"] = sym->ns;
  j["etree_height"] = sym->etree_height;
  j["super_etree_height"] = sym->super_etree_height;
  j["flops"] = sym->flops();
  j["order_s"] = median(order_s);
  j["symbolic_s"] = median(symbolic_s);
  j["numeric_s"] = median(numeric_s);
  j["solve_s"] = median(solve_s);
  j["solve8_s"] = median(solve8_s);
  j["factor_cache"] = {{"loaded", fo.cache.load.empty() ? Json(nullptr) : Json(fo.cache.load)},
                       {"saved", fo.cache.save.empty() ? Json(nullptr) : Json(fo.cache.save)},
                       {"load_s", median(load_s)},
                       {"save_s", save_s.back()}};
  j["residual"] = residual;
  j["residual8"] = residual8;
  // max_i |x8[i, lane 0] - x[i]| / max_i |x[i]|: the 8-lane path must agree with the 1-lane one.
  j["solve8_lane0_vs_solve"] = lane0_vs_solve;
  j["timings"] = timings(in, {{"operator_s", operator_s}});
  write_output_mesh(opt, output_faces(in), carried_attributes(in));
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": " << fo.op.kind << " operator";
    if (fo.op.kind == "heat") os << " (t = " << op.t << ", h = " << op.h << ")";
    os << "\n  n " << n << ", nnz(A) " << A.nnz() << ", nnz(L) " << sym->nnz_L << " (exact " << sym->nnz_exact
       << "), supernodes " << sym->ns << "\n  etree height " << sym->etree_height << ", supernodal etree height "
       << sym->super_etree_height << "\n  medians over " << fo.repeat << " run(s): order " << j["order_s"]
       << " s, symbolic " << j["symbolic_s"] << " s, numeric " << j["numeric_s"] << " s, solve " << j["solve_s"]
       << " s, solve8 " << j["solve8_s"] << " s\n"
       << (fo.cache.load.empty() ? std::string() : "  loaded from " + fo.cache.load + " in " + format_number(median(load_s)) + " s\n")
       << "  residual " << residual << ", 8-lane residual " << residual8
       << "\n";
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
