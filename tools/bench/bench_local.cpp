// `locus-bench local MESH [--subdivide K] [--threads N] --json`: the local
// solves of thesis chapter 4 against full solves and CHOLMOD, in one run.
//
// 1. Single source / single target heat value (§4.6, Fig. 4.9/4.12): heat
//    operator M - t L_C factored once; for --pairs random (source, target)
//    pairs, back to back per pair:
//      subset  — separate etree subtrees: forward from the source, backward to
//                the target (plan + solve, pipelines/heat_exchange)
//      union   — one subtree of {source, target} for both passes
//      full    — a full solve
//      CHOLMOD — cholmod_solve2 with Bset = {source, target} (b = 0 at the
//                target) on a simplicial copy of CHOLMOD's factor (the
//                supernodal-to-simplicial conversion is done once, untimed).
//                CHOLMOD is given locus's METIS ordering (cholmod_analyze_p),
//                so both walk the same elimination tree.
//    Also the single-entry value (A^{-1})_ii at --pairs random vertices: the
//    forward-only path walk (pipelines/adf), a subset solve (plan + forward +
//    backward), CHOLMOD Bset = {i}, a full solve. Reported: medians, the median
//    of the per-pair ratios, columns visited, the etree height. Lanes: an
//    8-lane subset solve against 8 one-lane ones, and a 24-lane one (24
//    random sources and targets, kernels/solve_wide) against three 8-lane ones.
// 2. Auto-diffusion at ALL vertices: selected inversion (kernels/
//    selected_inversion) vs the per-vertex path walk over all vertices (both
//    with --threads) vs full solves (median of --adf-sample single full solves
//    times n, one thread: an extrapolation). Above --adf-subset-limit vertices
//    the path walk is also extrapolated from a random sample of that many.
// 3. Patch parameterization (§4.4, Figs. 4.6/4.7): regularized Laplacian
//    factored once; for each patch size in --patch-sizes (sizes above n/2
//    skipped) and --patch-centers random centers:
//      local   — pipelines/patch_param: BFS patch, eq. 4.6 data, 8-lane subset
//                solve on the global factor, normalization, flip count
//      patch system — the same BFS patch extracted as a mesh, its own
//                regularized Laplacian, METIS ordering + symbolic + numeric
//                factorization, eq. 4.6 data and an 8-lane full solve (the
//                classical approach; BFS growing is common to both and timed
//                in both).
// 4. Circle-boundary patch map (pipelines/patch_param_circle): the same
//    patches with holes filled and the boundary fixed on a circle; the local
//    route updates the global factor to K_II (factor once, chapter 5), the
//    peer orders and factors K_II from scratch; both solve the same system.
// Ratios are peer / locus-local (> 1: the local solve is faster). Sections 1-2
// are in local_heat_values.cpp, 3-4 in local_patches.cpp.
#include <oneapi/tbb/info.h>

#include <iostream>
#include <memory>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "tools/bench/bench_local.hpp"

namespace locus::bench {
namespace {

using cli::Json;
using cli::Stopwatch;
using local::Options;

int run_bench_local(const cli::CommonOptions& opt, const Options& bo, const RunContext& ctx) {
  const cli::TimeSpec spec = cli::parse_time_spec(bo.t_text);
  cli::Input in = cli::load_input(opt, ctx);
  const Mesh& m = in.mesh;
  check_requirements(m, MeshRequirements{});
  const double h = mean_edge_length(m);
  const int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
  Json j{{"command", "bench local"}, {"input", cli::input_json(opt, in)}};
  j["n"] = m.num_vertices();
  j["threads"] = threads;
  j["seed"] = opt.seed;
  j["h"] = h;
  cli::log("bench local: heat values (" + std::to_string(bo.pairs) + " pairs)");
  j["heat"] = local::bench_pairs(m, spec.resolve(h), bo, opt.seed, ctx);
  if (!bo.skip_patch) {
    cli::log("bench local: patch parameterization");
    Stopwatch fsw;
    const CscMatrix K = regularized_laplacian(m);
    const NumericFactor F = factorize(analyze(K, order_matrix(K)), K, ctx);
    const double global_factor_s = fsw.seconds();
    j["patch"] = local::bench_patches(m, F, bo, opt.seed, ctx);
    j["patch"]["global_factor_s"] = global_factor_s;
    cli::log("bench local: circle-boundary patch map (factor-once update)");
    j["patch_circle"] = local::bench_circle_patches(m, K, F, bo, opt.seed, ctx);
  }
  j["timings"] = {{"load_s", in.load_s}, {"subdivide_s", in.subdivide_s}};
  std::cerr << j.dump(1) << "\n";
  if (opt.json) cli::emit(opt, j, {});
  return 0;
}

}  // namespace

void register_local_bench(cli::CommandTable& table) {
  auto bo = std::make_shared<Options>();
  CLI::App* app = table.add(
      "local", "Local solves (thesis ch. 4): heat values, auto-diffusion at all vertices, patch parameterization",
      [bo](const cli::CommonOptions& opt, const RunContext& ctx) { return run_bench_local(opt, *bo, ctx); });
  app->add_option("--t", bo->t_text, "Diffusion time of the heat operator (default 1h2)");
  app->add_option("--pairs", bo->pairs, "Random pairs / vertices for the single values (default 100)")
      ->check(CLI::Range(1, 1000000));
  app->add_option("--adf-sample", bo->adf_sample, "Full solves to extrapolate the all-vertex full method (default 100)")
      ->check(CLI::Range(1, 1000000));
  app->add_option("--adf-subset-limit", bo->adf_subset_limit,
                  "Above this n the all-vertex path walk is extrapolated from this many random vertices (default 300000)")
      ->check(CLI::Range(1, 1 << 30));
  app->add_option("--patch-sizes", bo->patch_sizes, "Patch vertex counts (default 2000,10000,30000,50000)");
  app->add_option("--patch-centers", bo->patch_centers, "Random centers per patch size (default 5)")
      ->check(CLI::Range(1, 10000));
  app->add_flag("--skip-adf", bo->skip_adf, "Skip the all-vertex auto-diffusion section");
  app->add_option("--ordering", bo->ordering, "Ordering of the heat section: auto (default), metis, nd, amd")
      ->check(CLI::IsMember({"auto", "metis", "nd", "amd"}));
  app->add_flag("--skip-patch", bo->skip_patch, "Skip the patch parameterization section");
}

}  // namespace locus::bench
