// SCOTCH's nested dissection as a peer of locus' orderings (thesis §4.2: the
// ordering's etree height decides the local solves' cost; SCOTCH,
// threaded since version 7, is the peer to measure or adopt).
//
// Not part of the library and not in the default build: Debian's libscotch-dev
// (CeCILL-C) is installed by `tools/setup.sh --bench-peers`, and
// `cmake --build build --target locus-bench-scotch` builds this program.
// Same heat operator as `locus-bench factor`, every ordering timed in one
// process, alternating within each repeat; SCOTCH's time includes building its
// graph from the matrix, as locus' includes building its adjacency. Fill,
// etree height and flops of every permutation come from locus' symbolic
// analysis, so they are counted the same way. Output: one JSON object.
#include <scotch/scotch.h>

#include <oneapi/tbb/info.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <functional>
#include <memory>
#include <iostream>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "tools/cli/cli_common.hpp"

namespace {

using namespace locus;
using cli::Json;
using cli::Stopwatch;

struct PeerOptions {
  int repeats = 3;
  std::string scotch_threads = "1,2";
  std::string strategy = "default";  // default, speed, quality (SCOTCH_stratGraphOrderBuild's flags)
};

// One SCOTCH ordering run: a context with `threads` threads (deterministic
// mode, so that thread counts can be compared) and the default strategy.
class ScotchOrdering {
 public:
  ScotchOrdering(int threads, SCOTCH_Num flags) : threads_(threads), flags_(flags) {}

  Ordering order(const CscMatrix& lower) const {
    const SCOTCH_Num n = lower.ncols;
    // Full symmetric adjacency without the diagonal, as SCOTCH wants it.
    std::vector<SCOTCH_Num> deg(static_cast<size_t>(n) + 1, 0);
    for (int32_t j = 0; j < n; ++j)
      for (int64_t p = lower.colptr[j]; p < lower.colptr[j + 1]; ++p)
        if (lower.rowind[p] != j) {
          ++deg[static_cast<size_t>(j) + 1];
          ++deg[static_cast<size_t>(lower.rowind[p]) + 1];
        }
    for (SCOTCH_Num j = 0; j < n; ++j) deg[j + 1] += deg[j];
    std::vector<SCOTCH_Num> edges(static_cast<size_t>(deg[n]));
    std::vector<SCOTCH_Num> fill(deg.begin(), deg.end() - 1);
    for (int32_t j = 0; j < n; ++j)
      for (int64_t p = lower.colptr[j]; p < lower.colptr[j + 1]; ++p) {
        const int32_t i = lower.rowind[p];
        if (i == j) continue;
        edges[fill[j]++] = i;
        edges[fill[i]++] = j;
      }
    SCOTCH_Graph graph, bound;
    SCOTCH_Context context;
    SCOTCH_Strat strat;
    check(SCOTCH_graphInit(&graph), "SCOTCH_graphInit");
    check(SCOTCH_graphBuild(&graph, 0, n, deg.data(), nullptr, nullptr, nullptr, deg[n], edges.data(), nullptr),
          "SCOTCH_graphBuild");
    SCOTCH_contextInit(&context);
    SCOTCH_contextOptionSetNum(&context, SCOTCH_OPTIONNUMDETERMINISTIC, 1);
    check(SCOTCH_contextThreadSpawn(&context, threads_, nullptr), "SCOTCH_contextThreadSpawn");
    SCOTCH_graphInit(&bound);
    check(SCOTCH_contextBindGraph(&context, &graph, &bound), "SCOTCH_contextBindGraph");
    SCOTCH_stratInit(&strat);
    if (flags_ != 0) check(SCOTCH_stratGraphOrderBuild(&strat, flags_, 0, 0.2), "SCOTCH_stratGraphOrderBuild");
    std::vector<SCOTCH_Num> permtab(static_cast<size_t>(n)), peritab(static_cast<size_t>(n));
    SCOTCH_Num blocks = 0;
    const int rc = SCOTCH_graphOrder(&bound, &strat, permtab.data(), peritab.data(), &blocks, nullptr, nullptr);
    SCOTCH_stratExit(&strat);
    SCOTCH_graphExit(&bound);
    SCOTCH_contextExit(&context);
    SCOTCH_graphExit(&graph);
    check(rc, "SCOTCH_graphOrder");
    Ordering ord;
    ord.perm.assign(peritab.begin(), peritab.end());  // SCOTCH's inverse permutation: new -> old
    ord.iperm.assign(permtab.begin(), permtab.end());
    return ord;
  }

 private:
  static void check(int rc, const char* what) {
    if (rc != 0) fail(ErrorCode::Numerical, std::string("bench scotch: ") + what + " failed (" + std::to_string(rc) + ")");
  }
  int threads_;
  SCOTCH_Num flags_;
};

struct Peer {
  std::string name;
  std::function<Ordering(const CscMatrix&)> order;
  std::vector<double> order_s;
  Ordering last;
};

OrderingOptions with_method(OrderingOptions::Method m) {
  OrderingOptions o;
  o.method = m;
  return o;
}

std::vector<int> parse_threads(const std::string& text) {
  std::vector<int> out;
  size_t at = 0;
  while (at <= text.size()) {
    const size_t comma = text.find(',', at);
    const std::string item = text.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
    int t = 0;
    try {
      t = std::stoi(item);
    } catch (const std::exception&) {
      t = 0;
    }
    if (t < 1 || t > 4096) fail(ErrorCode::BadUsage, "--scotch-threads: '" + item + "' is not a thread count");
    out.push_back(t);
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return out;
}

int run(const cli::CommonOptions& opt, const PeerOptions& po, const RunContext& ctx) {
  const std::vector<int> scotch_threads = parse_threads(po.scotch_threads);
  const SCOTCH_Num flags = po.strategy == "speed" ? SCOTCH_STRATSPEED : po.strategy == "quality" ? SCOTCH_STRATQUALITY : 0;
  cli::Input in = cli::load_input(opt, ctx);
  const cli::BuiltOperator op = cli::build_operator(in.mesh, cli::OperatorSpec{});
  const CscMatrix& A = op.A;
  std::vector<Peer> peers;
  auto locus_peer = [&](const std::string& name, OrderingOptions::Method m) {
    peers.push_back({name, [m, &ctx](const CscMatrix& M) { return order_matrix(M, with_method(m), ctx); }, {}, {}});
  };
  locus_peer("locus_auto", OrderingOptions::Method::Auto);
  locus_peer("locus_nd", OrderingOptions::Method::NestedDissection);
  locus_peer("locus_amd", OrderingOptions::Method::Amd);
  locus_peer("metis_nodend", OrderingOptions::Method::Metis);
  for (int t : scotch_threads)
    peers.push_back({"scotch_" + std::to_string(t) + "t", [t, flags](const CscMatrix& M) { return ScotchOrdering(t, flags).order(M); },
                     {}, {}});
  for (int r = 0; r < po.repeats; ++r)
    for (Peer& p : peers) {
      Stopwatch sw;
      p.last = p.order(A);
      p.order_s.push_back(sw.seconds());
      ctx.check_cancel();
    }
  Json j = {{"command", "bench scotch"}, {"input", cli::input_json(opt, in)}, {"n", A.ncols},
            {"threads", cli::threads_used(opt)}, {"repeats", po.repeats}, {"scotch_version", SCOTCH_VERSION},
            {"scotch_strategy", po.strategy}};
  Json rows = Json::object();
  double metis_nnz = 0, metis_height = 0;
  for (const Peer& p : peers) {
    const auto sym = analyze(A, p.last);
    rows[p.name] = {{"order_s", cli::median(p.order_s)},
                    {"nnz_L", sym->nnz_exact},
                    {"etree_height", sym->etree_height},
                    {"flops", static_cast<double>(sym->flops())}};
    if (p.name == "metis_nodend") {
      metis_nnz = static_cast<double>(sym->nnz_exact);
      metis_height = static_cast<double>(sym->etree_height);
    }
  }
  for (auto& [name, row] : rows.items()) {
    row["nnz_L_over_metis"] = row["nnz_L"].get<double>() / metis_nnz;
    row["etree_height_over_metis"] = row["etree_height"].get<double>() / metis_height;
  }
  // SCOTCH in deterministic mode: the same permutation for every thread count?
  if (scotch_threads.size() > 1) {
    bool same = true;
    for (const Peer& p : peers)
      if (p.name.rfind("scotch_", 0) == 0) same = same && p.last.perm == peers.back().last.perm;
    j["scotch_same_for_every_thread_count"] = same;
  }
  j["orderings"] = rows;
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    cli::CommandTable table("locus-bench-scotch", "SCOTCH's ordering against locus' (time, fill, etree height)");
    auto po = std::make_shared<PeerOptions>();
    CLI::App* app = table.add("order", "Order the heat operator of MESH with locus and SCOTCH; medians",
                              [po](const cli::CommonOptions& opt, const RunContext& ctx) { return run(opt, *po, ctx); });
    app->add_option("--repeats", po->repeats, "Repeats; medians are reported (default 3)")->check(CLI::Range(1, 1000));
    app->add_option("--scotch-threads", po->scotch_threads, "SCOTCH thread counts, comma-separated (default 1,2)");
    app->add_option("--strategy", po->strategy, "SCOTCH's ordering strategy: default, speed or quality")
        ->check(CLI::IsMember({"default", "speed", "quality"}));
    return table.run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "locus-bench-scotch: internal error: " << e.what() << "\n";
  }
  return 70;
}
