// Sections 3 and 4 of `locus-bench local` (bench_local.cpp describes them):
// patch parameterization by a local solve on the global factor against the
// patch's own system (thesis §4.4), and the circle-boundary patch map by the
// factor-once update (chapter 5) against ordering and factoring K_II anew.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/pipelines/param/patch_param.hpp"
#include "locus/pipelines/param/patch_param_circle.hpp"
#include "tools/bench/bench_local.hpp"
#include "tools/cli/vertex_list.hpp"

namespace locus::bench::local {

using cli::Json;
using cli::Stopwatch;

// ------------------------------------------------ 3. patch parameterization ----

// The --patch-sizes that fit a mesh of n vertices (10 .. n/2), logged when skipped.
std::vector<int32_t> patch_sizes(const Options& bo, int32_t n) {
  std::vector<int32_t> sizes;
  for (const std::string& item : cli::split_list(bo.patch_sizes, "--patch-sizes")) {
    const int32_t size = static_cast<int32_t>(std::stol(item));
    if (size < 10 || size > n / 2) cli::log("bench local: patch size " + item + " skipped (n = " + std::to_string(n) + ")");
    else sizes.push_back(size);
  }
  return sizes;
}

// F: the factor of m's regularized Laplacian (shared with section 4).
Json bench_patches(const Mesh& m, const NumericFactor& F, const Options& bo, uint64_t seed,
                   const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  Json j;
  Stopwatch sw;
  j["etree_height"] = F.symbolic->etree_height;
  const PatchGrower g = prepare_patch_grower(m);
  PatchWorkspace pws;
  SolveWorkspace ws;
  std::mt19937_64 rng(seed ^ 0x5bd1e995ULL);
  std::uniform_int_distribution<int32_t> pick(0, n - 1);
  Json rows = Json::array();
  for (const int32_t size : patch_sizes(bo, n)) {
    std::vector<double> local_s, sys_s, sys_factor_s, r, np, flips_local, flips_sys, fw, bw, grow_s, solve_s;
    for (int c = 0; c < bo.patch_centers; ++c) {
      ctx.check_cancel();
      const int32_t center = pick(rng);
      // (local) from the global factor.
      sw.restart();
      const PatchParam P = parameterize_patch(F, g, center, size, pws, ws);
      local_s.push_back(sw.seconds());
      grow_s.push_back(P.grow_s);
      solve_s.push_back(P.solve_s);
      // (patch system) extract, assemble, order, factor, solve.
      sw.restart();
      const MeshPatch patch = grow_patch(g, center, ring_patch(size), pws);
      const std::vector<std::vector<int32_t>> loops = boundary_loops(patch.mesh);
      size_t best = 0;
      for (size_t l = 1; l < loops.size(); ++l)
        if (loops[l].size() > loops[best].size()) best = l;
      const CscMatrix Kp = regularized_laplacian(patch.mesh);
      Stopwatch fsw;
      const NumericFactor Fp = factorize(analyze(Kp, order_matrix(Kp)), Kp);
      const double fs = fsw.seconds();
      const std::vector<double> b = circle_neumann_rhs(patch.mesh, loops[best]);
      const size_t pn = patch.vertices.size();
      std::vector<double> x8(pn * kLanes, 0.0);
      for (size_t k = 0; k < loops[best].size(); ++k) {
        x8[static_cast<size_t>(loops[best][k]) * kLanes] = b[2 * k];
        x8[static_cast<size_t>(loops[best][k]) * kLanes + 1] = b[2 * k + 1];
      }
      solve8(Fp, x8);
      std::vector<double> uv(2 * pn);
      for (size_t k = 0; k < pn; ++k) {
        uv[2 * k] = x8[k * kLanes];
        uv[2 * k + 1] = x8[k * kLanes + 1];
      }
      normalize_uv(uv);
      const UvFlips fl = count_uv_flips(patch.mesh, uv);
      sys_s.push_back(sw.seconds());
      sys_factor_s.push_back(fs);
      r.push_back(ratio(sys_s.back(), local_s.back()));
      np.push_back(static_cast<double>(P.patch.vertices.size()));
      flips_local.push_back(static_cast<double>(P.flips.flipped));
      flips_sys.push_back(static_cast<double>(fl.flipped));
      fw.push_back(static_cast<double>(P.forward_columns));
      bw.push_back(static_cast<double>(P.backward_columns));
    }
    rows.push_back({{"patch_size", size},
                    {"patch_vertices", cli::median(np)},
                    {"centers", bo.patch_centers},
                    {"local_s", cli::median(local_s)},
                    {"local_grow_s", cli::median(grow_s)},
                    {"local_solve_s", cli::median(solve_s)},
                    {"patch_system_s", cli::median(sys_s)},
                    {"patch_system_factor_s", cli::median(sys_factor_s)},
                    {"speedup_patch_system_over_local", cli::median(r)},
                    {"forward_columns", cli::median(fw)},
                    {"backward_columns", cli::median(bw)},
                    {"max_flips_local", *std::max_element(flips_local.begin(), flips_local.end())},
                    {"max_flips_patch_system", *std::max_element(flips_sys.begin(), flips_sys.end())}});
    cli::log("bench local: patches of " + std::to_string(size) + " done");
  }
  j["sizes"] = rows;
  return j;
}

// ------------------------------ 4. circle-boundary patch map (factor once) ----
// The same BFS patches (holes filled) with the boundary fixed on a circle:
//   local — pipelines/patch_param_circle: K_II's factor by the factor-once
//           update of the global factor (updater built once per mesh, reported
//           as updater_setup_s), Dirichlet data, refinement, flips;
//   patch system — the same patch and data, K_II extracted and factored from
//           scratch (METIS ordering + symbolic + numeric), the same solve.
// Both time patch growing, the system, the factorization and the solve; the
// two maps must agree (max_uv_difference, relative to the map's radius).
Json bench_circle_patches(const Mesh& m, const CscMatrix& K, const NumericFactor& F, const Options& bo,
                          uint64_t seed, const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  Json j;
  Stopwatch sw;
  const PatchGrower g = prepare_patch_grower(m);
  sw.restart();
  CirclePatchParameterizer cp(F, K, g);
  j["updater_setup_s"] = sw.seconds();
  DiskPatchWorkspace dws;
  std::mt19937_64 rng(seed ^ 0x5bd1e995ULL);
  std::uniform_int_distribution<int32_t> pick(0, n - 1);
  Json rows = Json::array();
  for (const int32_t size : patch_sizes(bo, n)) {
    std::vector<double> local_s, sys_s, r, np, holes, flips_local, flips_sys, upd_s, fac_s, diff, steps;
    std::vector<double> grow_s, system_s, solve_s, check_s;
    int refused = 0;
    for (int c = 0, tries = 0; c < bo.patch_centers && tries < 20 * bo.patch_centers; ++tries) {
      ctx.check_cancel();
      const int32_t center = pick(rng);
      sw.restart();
      CirclePatchParam P;
      try {
        P = cp.parameterize(center, size, ctx);
      } catch (const Error& e) {
        if (e.code() != ErrorCode::BadInput) throw;
        ++refused;  // not disk-like: the Neumann method's territory
        continue;
      }
      local_s.push_back(sw.seconds());
      ++c;
      // (patch system) the same patch, data and solve; K_II factored from scratch.
      sw.restart();
      const DiskPatch d = grow_disk_patch(g, center, size, dws);
      const CircleDirichletSystem sys = circle_dirichlet_system(K, d, dws);
      Stopwatch fsw;
      const CscMatrix Kii = principal_submatrix(K, sys.interior);
      const NumericFactor Fp = factorize(analyze(Kii, order_matrix(Kii)), Kii);
      const double fs = fsw.seconds();
      std::vector<double> uv_int(2 * sys.interior.size());
      const int st = solve_circle_dirichlet(Fp, Kii, sys, uv_int);
      std::vector<double> uv = assemble_patch_uv(d, sys, uv_int);
      normalize_uv(uv);
      const UvFlips fl = count_uv_flips(d.patch.mesh, uv);
      sys_s.push_back(sw.seconds());
      r.push_back(ratio(sys_s.back(), local_s.back()));
      double dmax = 0;
      for (size_t k = 0; k < uv.size() && k < P.uv.size(); ++k) dmax = std::max(dmax, std::abs(uv[k] - P.uv[k]));
      diff.push_back(uv.size() == P.uv.size() ? dmax : 1.0);
      np.push_back(static_cast<double>(P.disk.patch.vertices.size()));
      holes.push_back(static_cast<double>(P.disk.holes_filled));
      flips_local.push_back(static_cast<double>(P.flips.flipped + P.flips.degenerate));
      flips_sys.push_back(static_cast<double>(fl.flipped + fl.degenerate));
      upd_s.push_back(P.update_s);
      grow_s.push_back(P.grow_s);
      system_s.push_back(P.system_s);
      solve_s.push_back(P.solve_s);
      check_s.push_back(P.check_s);
      fac_s.push_back(fs);
      steps.push_back(std::max(P.refinement_steps, st));
    }
    if (local_s.empty()) {
      rows.push_back({{"patch_size", size}, {"refused_not_disk", refused}});
      continue;
    }
    rows.push_back({{"patch_size", size},
                    {"patch_vertices", cli::median(np)},
                    {"centers", local_s.size()},
                    {"refused_not_disk", refused},
                    {"holes_filled_median", cli::median(holes)},
                    {"local_s", cli::median(local_s)},
                    {"local_grow_s", cli::median(grow_s)},
                    {"local_system_s", cli::median(system_s)},
                    {"local_update_s", cli::median(upd_s)},
                    {"local_solve_s", cli::median(solve_s)},
                    {"local_check_s", cli::median(check_s)},
                    {"patch_system_s", cli::median(sys_s)},
                    {"patch_system_factor_s", cli::median(fac_s)},
                    {"speedup_patch_system_over_local", cli::median(r)},
                    {"min_speedup", *std::min_element(r.begin(), r.end())},
                    {"max_uv_difference", *std::max_element(diff.begin(), diff.end())},
                    {"max_refinement_steps", *std::max_element(steps.begin(), steps.end())},
                    {"max_flips_local", *std::max_element(flips_local.begin(), flips_local.end())},
                    {"max_flips_patch_system", *std::max_element(flips_sys.begin(), flips_sys.end())}});
    cli::log("bench local: circle patches of " + std::to_string(size) + " done");
  }
  j["sizes"] = rows;
  return j;
}

}  // namespace locus::bench::local
