// `locus heat MESH --source LIST --target LIST [--t T] [--method subset|union|full] [--repeat R] --json`:
// pairwise heat exchange (thesis §4.6): unit heat at every source (b = sum
// e_s), one backward-Euler step with M - t L_C, the heat at each target; a
// client of locus::Session::heat (engine/include/locus/engine/
// diffusion_requests.hpp), which owns the validation and the computation.
// subset uses separate etree subtrees for the forward (sources) and backward
// (targets) solve, union one subtree for both, full a full solve (reference).
// JSON: n, factor_s (ordering + symbolic + numeric), query_s (median over
// --repeat runs of plan + solve), plan_s / solve_s, the columns of L the query
// visited, the etree height, the values per target and their sum.
// --save F / --load F keep the factor of M - t L_C in a factor cache.
#include <ostream>

#include "locus/session.hpp"
#include "tools/cli/heat_signature.hpp"
#include "tools/cli/vertex_list.hpp"

namespace locus::cli {

namespace {

struct HeatCli {
  HeatRequest request;
  std::string sources, targets;  // --source / --target LIST as given
};

Json heat_json(const CommonOptions& opt, const Input& in, const HeatReport& r) {
  Json j{{"command", "heat"}, {"input", input_json(opt, in)}};
  j["method"] = r.method;
  j["n"] = r.n;
  j["t"] = r.t;
  j["t_spec"] = r.t_spec;
  j["h"] = r.h;
  j["sources"] = r.sources;
  j["targets"] = r.targets;
  j["values"] = r.values;
  j["total"] = r.total;
  j["nnz_L"] = r.nnz_L;
  j["etree_height"] = r.etree_height;
  j["forward_columns"] = r.forward_columns;
  j["backward_columns"] = r.backward_columns;
  j["factor_s"] = r.factor_s();
  j["query_s"] = r.query_s;
  j["plan_s"] = r.plan_s;
  j["solve_s"] = r.solve_s;
  j["repeats"] = r.repeats;
  j["factor_cache"] = factor_cache_json(r.factor_cache);
  j["timings"] = timings(in, {{"operator_s", r.operator_s},
                              {"order_s", r.order_s},
                              {"analyze_s", r.analyze_s},
                              {"numeric_s", r.numeric_s}});
  return j;
}

int run_heat(const CommonOptions& opt, HeatCli& ho, const RunContext& ctx) {
  refuse_output(opt, "heat", "the heat values are in the JSON (--json)");
  HeatRequest& q = ho.request;
  q.source = parse_vertex_ids(ho.sources, "--source");
  q.target = parse_vertex_ids(ho.targets, "--target");
  check_request(q);
  const Input in = load_input(opt, ctx);
  check_file_vertices(q.source, in.mesh.num_vertices(), "--source");
  check_file_vertices(q.target, in.mesh.num_vertices(), "--target");
  const Session session{Mesh(in.mesh), session_options(in)};
  const HeatReport r = session.heat(q, ctx);
  emit(opt, heat_json(opt, in, r), [&](std::ostream& os) {
    os << opt.mesh_path << ": heat exchange by " << r.method << ", t = " << r.t << ", n " << r.n
       << "\n  factor " << r.factor_s() << " s, query " << r.query_s << " s (columns forward " << r.forward_columns
       << ", backward " << r.backward_columns << ", etree height " << r.etree_height << ")\n";
    for (size_t k = 0; k < r.targets.size(); ++k) os << "  target " << r.targets[k] << ": " << r.values[k] << "\n";
  });
  return 0;
}

}  // namespace

void register_heat_command(CommandTable& table) {
  auto ho = std::make_shared<HeatCli>();
  CLI::App* app = table.add("heat", "Pairwise heat exchange (thesis 4.6): heat at targets from unit sources",
                            [ho](const CommonOptions& opt, const RunContext& ctx) { return run_heat(opt, *ho, ctx); });
  HeatRequest& q = ho->request;
  app->add_option("--source", ho->sources, "Comma-separated source vertex ids (unit heat each)")->required();
  app->add_option("--target", ho->targets, "Comma-separated target vertex ids")->required();
  app->add_option("--t", q.t, "Diffusion time: absolute (1e-3) or a multiple of h^2 (500h2); default 1h2")
      ->check(non_empty());
  app->add_option("--method", q.method, "subset (separate subtrees, default), union (one subtree) or full")
      ->check(CLI::IsMember({"subset", "union", "full"}));
  app->add_option("--repeat", q.repeat, "Repeat the query R times; median time (default 1)")
      ->check(CLI::Range(1, 100000));
  add_factor_cache_options(app, q.save, q.load);
}

}  // namespace locus::cli
