// `locus deform MESH`: region-of-interest deformation with a factor-once
// submesh factor (thesis §5.1, §5.7; pipelines/include/locus/pipelines/deform/deform.hpp). The global
// operator is factored once; the factor of A_FF for the free vertices comes
// from the update kernel; the handle offset is then one 8-lane solve. For
// comparison the same A_FF is ordered (METIS), analyzed and factored from
// scratch and solved again: `refactor_s` / `refactor_solve_s`, and the largest
// coordinate difference of the two results is reported.
#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/deform/deform.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

struct DeformOptions {
  int32_t roi_seed = -1;
  double roi_fraction = 0.1;
  int32_t handle = -1;
  int32_t handle_ring = 1;
  std::string offset_text;
  std::string energy = "laplacian";
  double regularization = 1e-6;
  FactorCacheOptions cache;
};

std::array<double, 3> parse_offset(const std::string& text) {
  const std::string msg = "--offset expects three finite numbers dx,dy,dz (e.g. --offset=-0.1,0,0.2), got '" + text + "'";
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t comma = text.find(',', start);
    parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (parts.size() != 3) fail(ErrorCode::BadUsage, msg);
  std::array<double, 3> v{};
  for (int k = 0; k < 3; ++k) {
    size_t used = 0;
    try {
      v[k] = std::stod(parts[k], &used);
    } catch (const std::exception&) {
      fail(ErrorCode::BadUsage, msg);
    }
    if (used != parts[k].size() || !std::isfinite(v[k])) fail(ErrorCode::BadUsage, msg);
  }
  return v;
}

int run_deform(const CommonOptions& opt, const DeformOptions& o, const RunContext& ctx) {
  const DeformEnergy energy = parse_deform_energy(o.energy);
  const std::array<double, 3> offset = parse_offset(o.offset_text);
  if (!(o.regularization > 0) || !std::isfinite(o.regularization))
    fail(ErrorCode::BadUsage, "--regularization must be a positive number");
  validate_factor_cache_options(o.cache);
  Input in = load_input(opt, ctx);
  const Mesh& mesh = in.mesh;
  const int32_t nv = mesh.num_vertices();
  // Ids are checked before the global factorization so that a typo fails fast.
  for (const auto& [name, v] : {std::pair<const char*, int32_t>{"--roi-seed", o.roi_seed}, {"--handle", o.handle}})
    if (v < 0 || v >= nv)
      fail(v < 0 ? ErrorCode::BadUsage : ErrorCode::BadInput, std::string(name) + " " + std::to_string(v) + " is not a vertex id (the mesh has " +
                                    std::to_string(nv) + " vertices)");
  ctx.check_cancel();

  // The global operator: prepare_deform_operator's steps, with the factor from the cache when asked.
  DeformOperator op;
  op.energy = energy;
  Stopwatch osw;
  op.mats = deform_matrices(mesh, energy, o.regularization);
  op.operator_s = osw.seconds();
  ctx.check_cancel();
  // The label carries the energy; t holds the relative regularization (it changes the matrix).
  const FactorRequest req{std::string("deform-") + deform_energy_name(energy), o.regularization, &op.mats.A};
  Factors global = factor_or_load(o.cache, mesh, std::span(&req, 1), ctx);
  op.L = std::move(global.factors[0]);
  op.order_s = global.order_s;
  op.analyze_s = global.analyze_s;
  op.factor_s = global.numeric_s;
  ctx.check_cancel();
  Stopwatch sw;
  const Adjacency adj = vertex_adjacency(mesh);
  const DeformRegion region = make_deform_region(adj, o.roi_seed, o.roi_fraction, o.handle, o.handle_ring);
  const double region_s = sw.seconds();

  sw.restart();
  const DeformSystem sys = prepare_deform_system(op, region, ctx);
  const double system_s = sw.seconds();  // update + E_FF + coupling to the known vertices
  const double update_s = sys.update_s;
  ctx.check_cancel();

  const Mesh target = handle_target(mesh, region, offset);
  Mesh out;
  sw.restart();
  const DeformSolveStats st = solve_deformation(sys.sub.factor, sys, mesh, target, out);
  const double solve_s = sw.seconds();
  ctx.check_cancel();

  // Baseline: A_FF from scratch (METIS + symbolic + numeric), then the same solve.
  const CscMatrix& Aff = sys.sub.A_sub;
  sw.restart();
  const Ordering ord = order_matrix(Aff);
  auto S = analyze(Aff, ord);
  const NumericFactor Fs = factorize(S, Aff, ctx);
  const double refactor_s = sw.seconds();
  ctx.check_cancel();
  Mesh out_ref;
  sw.restart();
  solve_deformation(Fs, sys, mesh, target, out_ref);
  const double refactor_solve_s = sw.seconds();
  double diff = 0, moved = 0;
  for (int32_t v = 0; v < nv; ++v) {
    diff = std::max({diff, std::abs(out.x[v] - out_ref.x[v]), std::abs(out.y[v] - out_ref.y[v]),
                     std::abs(out.z[v] - out_ref.z[v])});
    moved = std::max(moved, std::sqrt((out.x[v] - mesh.x[v]) * (out.x[v] - mesh.x[v]) +
                                      (out.y[v] - mesh.y[v]) * (out.y[v] - mesh.y[v]) +
                                      (out.z[v] - mesh.z[v]) * (out.z[v] - mesh.z[v])));
  }

  const FactorUpdateStats& us = sys.sub.stats;
  Json j{{"command", "deform"}, {"input", input_json(opt, in)}};
  j["energy"] = deform_energy_name(energy);
  j["regularization"] = o.regularization;
  j["roi_seed"] = o.roi_seed;
  j["roi_fraction"] = o.roi_fraction;
  j["handle"] = o.handle;
  j["handle_ring"] = o.handle_ring;
  j["offset"] = {offset[0], offset[1], offset[2]};
  j["threads"] = threads_used(opt);
  j["n"] = nv;
  j["roi_vertices"] = region.roi.size();
  j["handle_vertices"] = region.handle.size();
  j["free_vertices"] = region.free.size();
  j["fixed_vertices"] = static_cast<int64_t>(nv) - static_cast<int64_t>(region.roi.size());
  j["global_factor_s"] = op.order_s + op.analyze_s + op.factor_s;
  j["update_s"] = update_s;
  j["system_s"] = system_s;
  j["solve_s"] = solve_s;
  j["refactor_s"] = refactor_s;
  j["refactor_solve_s"] = refactor_solve_s;
  j["speedup_update_vs_refactor"] = update_s > 0 ? refactor_s / update_s : 0.0;
  j["columns_updated_fraction"] = us.columns_updated_fraction;
  j["supernodes_recomputed"] = us.supernodes_recomputed;
  j["supernodes"] = us.supernodes;
  j["values_stored_update"] = us.values_stored;
  j["values_stored_refactor"] = S->nnz_L;
  j["refinement_steps"] = st.refinement_steps;
  j["residual"] = st.residual;
  j["max_displacement"] = moved;
  j["update_vs_refactor_max_diff"] = diff;
  j["factor_cache"] = factor_cache_json(o.cache, global);
  j["timings"] = timings(in, {{"operator_s", op.operator_s},
                  {"order_s", op.order_s},         {"analyze_s", op.analyze_s},     {"factor_s", op.factor_s},
                  {"region_s", region_s},          {"update_structure_s", us.structure_s},
                  {"update_mark_s", us.mark_s},    {"update_copy_s", us.copy_s},    {"update_factor_s", us.factor_s}});
  write_output_mesh(opt, with_positions(in, out), carried_attributes(in, /*positions_changed=*/true));
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": " << deform_energy_name(energy) << " deformation, " << nv << " vertices; ROI "
       << region.roi.size() << " (handle " << region.handle.size() << ", free " << region.free.size() << ")\n"
       << "  global factor " << j["global_factor_s"] << " s (once per mesh)\n"
       << "  update " << update_s << " s (" << 100.0 * us.columns_updated_fraction << "% of columns recomputed), solve "
       << solve_s << " s (" << st.refinement_steps << " refinement steps, residual " << st.residual << ")\n"
       << "  from scratch: analyze+factor " << refactor_s << " s, solve " << refactor_solve_s << " s; max difference "
       << diff << "\n";
  });
  return 0;
}

}  // namespace

void register_deform_command(CommandTable& table) {
  auto o = std::make_shared<DeformOptions>();
  CLI::App* app = table.add("deform", "Move a handle inside a region of interest (factor-once submesh update)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_deform(opt, *o, ctx); });
  app->add_option("--roi-seed", o->roi_seed, "Vertex the region of interest grows from (BFS)")->required();
  app->add_option("--roi-fraction", o->roi_fraction, "Fraction of the vertices in the region of interest (default 0.1)")
      ->check(CLI::Range(0.0, 1.0));
  app->add_option("--handle", o->handle, "Handle vertex (inside the region of interest)")->required();
  app->add_option("--handle-ring", o->handle_ring, "Handle = the handle vertex and its k-ring in the ROI (default 1)")
      ->check(CLI::Range(0, 1000));
  app->add_option("--offset", o->offset_text, "Handle displacement dx,dy,dz")->required();
  app->add_option("--energy", o->energy, "laplacian (default) or bilaplacian");
  app->add_option("--regularization", o->regularization,
                  "Relative eps of -L_C + eps M in the factored global operator (default 1e-6); the solve "
                  "refines to the exact energy");
  add_factor_cache_options(app, o->cache);
}

}  // namespace locus::cli
