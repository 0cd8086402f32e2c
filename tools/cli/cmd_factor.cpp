// `locus factor MESH`: the numeric core end to end on one mesh matrix
// (DESIGN.md "Numeric core" 1-5), computed by locus::Session::factor
// (engine/include/locus/engine/factor_request.hpp): METIS ordering, symbolic
// analysis, supernodal numeric factorization, a 1-lane and an 8-lane full
// solve, with per-phase medians over --repeat runs and the relative residual
// ||A x - b|| / ||b|| of a seeded random right-hand side as the quality
// check. --load F replaces ordering, analysis and factorization by loading F
// (each repeat; order_s, symbolic_s, numeric_s are then 0 and
// factor_cache.load_s is the median load time); --save F writes the factor
// of the last repeat. This file translates the options and presents the report.
#include <ostream>
#include <string>

#include "locus/engine/factor_request.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

Json factor_json(const CommonOptions& opt, const Input& in, const FactorCommandReport& r) {
  Json j{{"command", "factor"}, {"input", input_json(opt, in)}};
  j["operator"] = r.matrix;
  j["t"] = r.t;
  j["h"] = r.h;
  j["seed"] = opt.seed;
  j["threads"] = threads_used(opt);
  j["repeats"] = r.repeats;
  j["n"] = r.n;
  j["nnz_A"] = r.nnz_A;
  j["nnz_L"] = r.nnz_L;
  j["nnz_L_exact"] = r.nnz_L_exact;
  j["supernodes"] = r.supernodes;
  j["etree_height"] = r.etree_height;
  j["super_etree_height"] = r.super_etree_height;
  j["flops"] = r.flops;
  j["order_s"] = r.order_s;
  j["symbolic_s"] = r.symbolic_s;
  j["numeric_s"] = r.numeric_s;
  j["solve_s"] = r.solve_s;
  j["solve8_s"] = r.solve8_s;
  j["factor_cache"] = factor_cache_json(r.factor_cache);
  j["residual"] = r.residual;
  j["residual8"] = r.residual8;
  // max_i |x8[i, lane 0] - x[i]| / max_i |x[i]|: the 8-lane path must agree with the 1-lane one.
  j["solve8_lane0_vs_solve"] = r.lane0_vs_solve;
  j["timings"] = timings(in, {{"operator_s", r.operator_s}});
  return j;
}

int run_factor(const CommonOptions& opt, FactorCommandRequest& q, const RunContext& ctx) {
  q.seed = opt.seed;
  check_request(q);  // bad usage before reading the file
  const Input in = load_input(opt, ctx);
  const Session session{Mesh(in.mesh), session_options(in)};
  const FactorCommandReport r = session.factor(q, ctx);
  const Json j = factor_json(opt, in, r);
  write_output_mesh(opt, output_faces(in), carried_attributes(in));
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": " << r.matrix << " operator";
    if (r.matrix == "heat") os << " (t = " << r.t << ", h = " << r.h << ")";
    os << "\n  n " << r.n << ", nnz(A) " << r.nnz_A << ", nnz(L) " << r.nnz_L << " (exact " << r.nnz_L_exact
       << "), supernodes " << r.supernodes << "\n  etree height " << r.etree_height << ", supernodal etree height "
       << r.super_etree_height << "\n  medians over " << r.repeats << " run(s): order " << j["order_s"]
       << " s, symbolic " << j["symbolic_s"] << " s, numeric " << j["numeric_s"] << " s, solve " << j["solve_s"]
       << " s, solve8 " << j["solve8_s"] << " s\n"
       << (q.load.empty() ? std::string()
                          : "  loaded from " + q.load + " in " + format_number(r.factor_cache.load_s) + " s\n")
       << "  residual " << r.residual << ", 8-lane residual " << r.residual8 << "\n";
  });
  return 0;
}

}  // namespace

void register_factor_command(CommandTable& table) {
  auto q = std::make_shared<FactorCommandRequest>();
  CLI::App* app = table.add("factor", "Order, analyze, factor and solve a mesh operator; timings and residual",
                            [q](const CommonOptions& opt, const RunContext& ctx) { return run_factor(opt, *q, ctx); });
  add_matrix_options(app, q->matrix, q->t);
  app->add_option("--repeat,--repeats", q->repeat, "Repeat the pipeline R times and report medians (default 1)")
      ->check(CLI::Range(1, 1000));
  add_factor_cache_options(app, q->save, q->load);
}

}  // namespace locus::cli
