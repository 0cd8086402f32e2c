// `locus-bench robust MESH [--subdivide K] [--repeat R] --json`: what the robust
// operator (engine/include/locus/engine/operator_choice.hpp; Sharp & Crane,
// SGP 2020) costs against the cotan operator on the same mesh, for the first
// answer a user waits for: a Session built on the mesh (its checks; with auto,
// the defect detection in the same pass) and its first whole-mesh geodesic
// distance (building and factoring the heat method's operators, one query).
// Rows: cotan, auto (on a clean mesh: cotan after the defect check) and robust
// (tufted cover, mollification, intrinsic Delaunay flips, intrinsic gradients);
// medians over --repeat runs, and robust / cotan. The robust operator's own
// build (robust_laplacian) is timed apart.
#include <algorithm>
#include <iostream>
#include <memory>
#include <vector>

#include "locus/kernels/mesh/robust_laplacian.hpp"
#include "locus/session.hpp"
#include "tools/bench/bench_commands.hpp"

namespace locus::bench {
namespace {

using cli::Json;
using cli::Stopwatch;

struct Row {
  std::vector<double> session_s, first_s;
  bool robust = false;
};

int run_robust(const cli::CommonOptions& opt, int repeat, const RunContext& ctx) {
  const cli::Input in = cli::load_input(opt, ctx);
  const Mesh& m = in.mesh;
  Json rows = Json::object();
  double cotan_total = 0;
  for (const OperatorChoice c : {OperatorChoice::Cotan, OperatorChoice::Auto, OperatorChoice::Robust}) {
    Row r;
    for (int k = 0; k < repeat; ++k) {
      ctx.check_cancel();
      SessionOptions so;
      so.mesh_operator = c;
      Stopwatch sw;
      const Session s(Mesh(m), so);
      r.session_s.push_back(sw.seconds());
      sw.restart();
      const std::vector<double> d = s.geodesic_distance(0, {}, ctx);
      r.first_s.push_back(sw.seconds());
      r.robust = s.operator_report().robust;
    }
    const double ss = cli::median(r.session_s), fs = cli::median(r.first_s);
    if (c == OperatorChoice::Cotan) cotan_total = ss + fs;
    rows[operator_choice_name(c)] = {{"operator_used", r.robust ? "robust" : "cotan"},
                                     {"session_s", ss},
                                     {"first_geodesic_s", fs},
                                     {"first_answer_s", ss + fs},
                                     {"vs_cotan", (ss + fs) / cotan_total}};
  }
  std::vector<double> build_s;
  for (int k = 0; k < repeat; ++k) {
    Stopwatch sw;
    const RobustOperators R = robust_laplacian(m);
    build_s.push_back(sw.seconds());
  }
  Json j{{"command", "robust"}, {"input", cli::input_json(opt, in)}, {"threads", cli::threads_used(opt)},
         {"repeat", repeat}, {"rows", rows}, {"robust_laplacian_s", cli::median(build_s)}};
  cli::emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": first answer (Session + first whole-mesh geodesic), medians of " << repeat << "\n";
    for (const auto& [name, row] : rows.items())
      os << "  " << name << " (" << row["operator_used"].get<std::string>() << "): " << row["first_answer_s"]
         << " s, " << row["vs_cotan"] << "x cotan\n";
    os << "  robust_laplacian alone: " << cli::median(build_s) << " s\n";
  });
  return 0;
}

}  // namespace

void register_robust_bench(cli::CommandTable& table) {
  auto repeat = std::make_shared<int>(3);
  CLI::App* app = table.add("robust", "First answer on the robust operator vs the cotan operator (Session + geodesic)",
                            [repeat](const cli::CommonOptions& o, const RunContext& ctx) {
                              return run_robust(o, *repeat, ctx);
                            });
  cli::drop_mesh_operator_option(app);  // every operator is measured
  app->add_option("--repeat", *repeat, "Runs per row; medians (default 3)")->check(CLI::Range(1, 100));
}

}  // namespace locus::bench
