// `locus heat MESH --source LIST --target LIST [--t T] [--method subset|union|full] [--repeat R] --json`:
// pairwise heat exchange (thesis §4.6, pipelines/include/locus/pipelines/heat/heat_exchange.hpp): unit heat
// at every source (b = sum e_s), one backward-Euler step with M - t L_C, the
// heat at each target. subset uses separate etree subtrees for the forward
// (sources) and backward (targets) solve, union one subtree for both, full a
// full solve (reference).
// JSON: n, factor_s (ordering + symbolic + numeric), query_s (median over
// --repeat runs of plan + solve), plan_s / solve_s, the columns of L the query
// visited, the etree height, the values per target and their sum.
// --save F / --load F keep the factor of M - t L_C in a factor cache.
#include <cmath>
#include <ostream>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/heat/heat_exchange.hpp"
#include "tools/cli/heat_signature.hpp"
#include "tools/cli/vertex_list.hpp"

namespace locus::cli {

namespace {

struct HeatCliOptions {
  std::string sources, targets;
  std::string t_text = "1h2";
  std::string method = "subset";
  int repeat = 1;
  FactorCacheOptions cache;
};

int run_heat(const CommonOptions& opt, const HeatCliOptions& ho, const RunContext& ctx) {
  refuse_output(opt, "heat", "the heat values are in the JSON (--json)");
  const HeatExchangeMethod method = parse_heat_exchange_method(ho.method);
  const TimeSpec spec = parse_time_spec(ho.t_text);
  validate_factor_cache_options(ho.cache);
  Input in = load_input(opt, ctx);
  const Mesh& m = in.mesh;
  const std::string where = m.source.empty() ? std::string("the mesh") : m.source;
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, where + " has no faces");
  check_input_operator(in);
  const double h = mean_edge_length(m);
  if (!(h > 0) || !std::isfinite(h)) fail(ErrorCode::BadInput, where + ": mean edge length is " + format_number(h));
  const std::vector<int32_t> S = parse_vertex_list(ho.sources, m.num_vertices(), "--source");
  const std::vector<int32_t> T = parse_vertex_list(ho.targets, m.num_vertices(), "--target");
  const double t = spec.resolve(h);

  Stopwatch osw;
  const CscMatrix A = input_heat_operator(in, t);
  const double operator_s = osw.seconds();
  const FactorRequest req{"heat", t, &A};
  const Factors H = factor_or_load(ho.cache, m, std::span(&req, 1), ctx);
  const double factor_s = H.factor_s();
  HeatWorkspace ws;
  std::vector<double> out(T.size());
  std::vector<double> query_s, plan_s, solve_s;
  HeatExchangeStats st;
  for (int r = 0; r < ho.repeat; ++r) {
    ctx.check_cancel();
    Stopwatch sw;
    heat_exchange(H.factors[0], S, T, method, out, ws, &st);
    query_s.push_back(sw.seconds());
    plan_s.push_back(st.plan_s);
    solve_s.push_back(st.solve_s);
  }
  double total = 0;
  for (size_t k = 0; k < out.size(); ++k) {
    if (!std::isfinite(out[k]))
      fail(ErrorCode::Numerical, "heat: the value at target " + std::to_string(T[k]) + " is " + format_number(out[k]));
    total += out[k];
  }

  Json j{{"command", "heat"}, {"input", input_json(opt, in)}};
  j["method"] = heat_exchange_method_name(method);
  j["n"] = m.num_vertices();
  j["t"] = t;
  j["t_spec"] = ho.t_text;
  j["h"] = h;
  j["sources"] = S;
  j["targets"] = T;
  j["values"] = out;
  j["total"] = total;
  j["nnz_L"] = H.symbolic->nnz_L;
  j["etree_height"] = H.symbolic->etree_height;
  j["forward_columns"] = st.forward_columns;
  j["backward_columns"] = st.backward_columns;
  j["factor_s"] = factor_s;
  j["query_s"] = median(query_s);
  j["plan_s"] = median(plan_s);
  j["solve_s"] = median(solve_s);
  j["repeats"] = ho.repeat;
  j["factor_cache"] = factor_cache_json(ho.cache, H);
  j["timings"] = timings(in, {{"operator_s", operator_s},
                  {"order_s", H.order_s}, {"analyze_s", H.analyze_s}, {"numeric_s", H.numeric_s}});
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": heat exchange by " << heat_exchange_method_name(method) << ", t = " << t << ", n "
       << m.num_vertices() << "\n  factor " << factor_s << " s, query " << median(query_s) << " s (columns forward "
       << st.forward_columns << ", backward " << st.backward_columns << ", etree height " << H.symbolic->etree_height
       << ")\n";
    for (size_t k = 0; k < T.size(); ++k) os << "  target " << T[k] << ": " << out[k] << "\n";
  });
  return 0;
}

}  // namespace

void register_heat_command(CommandTable& table) {
  auto ho = std::make_shared<HeatCliOptions>();
  CLI::App* app = table.add("heat", "Pairwise heat exchange (thesis 4.6): heat at targets from unit sources",
                            [ho](const CommonOptions& opt, const RunContext& ctx) { return run_heat(opt, *ho, ctx); });
  app->add_option("--source", ho->sources, "Comma-separated source vertex ids (unit heat each)")->required();
  app->add_option("--target", ho->targets, "Comma-separated target vertex ids")->required();
  app->add_option("--t", ho->t_text, "Diffusion time: absolute (1e-3) or a multiple of h^2 (500h2); default 1h2")->check(non_empty());
  app->add_option("--method", ho->method, "subset (separate subtrees, default), union (one subtree) or full")
      ->check(CLI::IsMember({"subset", "union", "full"}));
  app->add_option("--repeat", ho->repeat, "Repeat the query R times; median time (default 1)")
      ->check(CLI::Range(1, 100000));
  add_factor_cache_options(app, ho->cache);
}

}  // namespace locus::cli
