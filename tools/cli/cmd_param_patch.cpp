// The patch mode of `locus param` (tools/cli/param_patch.hpp): thesis §4.4.
//
// The whole mesh's regularized cotan Laplacian -L_C + eps M is ordered and
// factored once; the patch is the BFS patch of round(fraction * n) vertices
// around --center (kernels/mesh/patch_grower, Rings mode); its boundary loop on a circle gives the
// Neumann data of eq. 4.6; u and v come from one 8-lane subset solve with the
// patch vertices as the wanted set (exact: the full solve's values there), then
// are centered and scaled into the unit disk. --method does not apply: the patch
// mode always uses the global cotan operator (that is the point of §4.4).
//
// -o FILE writes the PATCH as a mesh of its own (vertex k = k-th patch vertex)
// with the parameterization as texture coordinates (OBJ `vt`, PLY u/v).
// JSON: n, factor_s (order + symbolic + numeric of the global operator),
// query_s (patch growing + data + subset solve + normalization + flip check),
// the patch and boundary sizes, Euler characteristic, flipped / degenerate
// faces (orientation against the majority), the columns of L the solve visited.
// --save F / --load F keep the global factor in a factor cache.
//
// --boundary circle: the same patch with enclosed holes filled, its boundary
// loop FIXED on a circle (arc length), the interior's factor from the global
// factor by the factor-once update (pipelines/patch_param_circle): the harmonic
// map with convex boundary, flip-free where the cotan weights are positive.
// JSON adds holes_filled, vertices_added, refinement_steps and the update's
// columns; query_s = growing + system + update + solve + checks.
#include <cmath>
#include <ostream>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/param/patch_param.hpp"
#include "locus/pipelines/param/patch_param_circle.hpp"
#include "tools/cli/param_patch.hpp"
#include "tools/cli/written_files.hpp"

namespace locus::cli {

namespace {

// --boundary circle, after the global factor exists.
int run_circle(const CommonOptions& opt, const Input& in, const CscMatrix& K, const Factors& Fs, int32_t center,
               double fraction, const FactorCacheOptions& cache, double operator_s, const RunContext& ctx) {
  const Mesh& m = in.mesh;
  Stopwatch sw;
  const PatchGrower grower = prepare_patch_grower(m);
  CirclePatchParameterizer cp(Fs.factors[0], K, grower);
  const double prepare_s = sw.seconds();
  sw.restart();
  const CirclePatchParam P = cp.parameterize(center, patch_vertex_count(m.num_vertices(), fraction), ctx);
  const double query_s = sw.seconds();
  for (double v : P.uv)
    if (!std::isfinite(v)) fail(ErrorCode::Numerical, "param: the patch parameterization is not finite");
  const MeshPatch& patch = P.disk.patch;
  if (!opt.output.empty()) {
    WriteOptions wo;
    wo.uv = &P.uv;
    write_mesh(opt.output, patch.mesh, wo);
    log_written(opt.output);
  }
  Json j{{"command", "param"}, {"input", input_json(opt, in)}};
  j["domain"] = "patch";
  j["boundary"] = "circle";
  j["operator"] = "cotan Laplacian, patch boundary fixed on a circle; factor of the interior by the factor-once update "
                  "of the global -L_C + eps M, eps removed by preconditioned CG";
  j["n"] = m.num_vertices();
  j["center"] = center;
  j["fraction"] = fraction;
  j["patch_vertices"] = patch.vertices.size();
  j["patch_faces"] = patch.faces.size();
  j["bfs_rings"] = patch.rings;
  j["boundary_vertices"] = P.disk.boundary.size();
  j["boundary_loops"] = 1;
  j["holes_filled"] = P.disk.holes_filled;
  j["vertices_added"] = P.disk.vertices_added;
  j["euler_characteristic"] = P.disk.euler_characteristic;
  j["interior_vertices"] = P.interior;
  j["refinement_steps"] = P.refinement_steps;
  j["flipped_faces"] = P.flips.flipped;
  j["degenerate_faces"] = P.flips.degenerate;
  j["orientation"] = P.flips.orientation;
  j["etree_height"] = Fs.symbolic->etree_height;
  j["update"] = {{"supernodes", P.update.supernodes},
                 {"supernodes_recomputed", P.update.supernodes_recomputed},
                 {"columns_recomputed", P.update.columns_recomputed},
                 {"values_stored", P.update.values_stored}};
  j["factor_s"] = Fs.order_s + Fs.analyze_s + Fs.numeric_s;
  j["query_s"] = query_s;
  j["factor_cache"] = factor_cache_json(cache, Fs);
  j["timings"] = timings(in, {{"operator_s", operator_s},
                  {"order_s", Fs.order_s},   {"analyze_s", Fs.analyze_s},     {"numeric_s", Fs.numeric_s},
                  {"prepare_s", prepare_s},  {"grow_s", P.grow_s},            {"system_s", P.system_s},
                  {"update_s", P.update_s},  {"solve_s", P.solve_s},          {"check_s", P.check_s}});
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": patch of " << patch.vertices.size() << " vertices around " << center
       << " (boundary " << P.disk.boundary.size() << " vertices on a circle, " << P.disk.holes_filled
       << " hole(s) filled, Euler characteristic " << P.disk.euler_characteristic << ")\n  flipped faces "
       << P.flips.flipped << ", degenerate faces " << P.flips.degenerate << "\n  factor " << j["factor_s"]
       << " s, patch " << query_s << " s\n";
  });
  return 0;
}

}  // namespace

int run_param_patch(const CommonOptions& opt, int32_t center, double fraction, const std::string& boundary,
                    const FactorCacheOptions& cache, const RunContext& ctx) {
  if (boundary != "neumann" && boundary != "circle")
    fail(ErrorCode::BadUsage, "--boundary must be neumann or circle, got '" + boundary + "'");
  if (!(fraction > 0.0 && fraction <= 1.0))
    fail(ErrorCode::BadUsage, "--fraction must be in (0, 1], got " + format_number(fraction));
  validate_factor_cache_options(cache);
  check_uv_output(opt, "param");
  Input in = load_input(opt, ctx);
  const Mesh& m = in.mesh;
  const std::string where = m.source.empty() ? std::string("the mesh") : m.source;
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, where + " has no faces");
  check_requirements(m, MeshRequirements{});
  if (center < 0 || center >= m.num_vertices())
    fail(center < 0 ? ErrorCode::BadUsage : ErrorCode::BadInput, "--center " + std::to_string(center) + " is outside 0.." +
                                  std::to_string(m.num_vertices() - 1));
  ctx.check_cancel();

  Stopwatch sw;
  const CscMatrix K = regularized_laplacian(m);
  const double operator_s = sw.seconds();
  const FactorRequest req{"laplacian", 0, &K};
  const Factors Fs = factor_or_load(cache, m, std::span(&req, 1), ctx);
  const NumericFactor& F = Fs.factors[0];
  const std::shared_ptr<const SymbolicFactor>& sym = Fs.symbolic;
  const double order_s = Fs.order_s, analyze_s = Fs.analyze_s, numeric_s = Fs.numeric_s;
  ctx.check_cancel();
  if (boundary == "circle") return run_circle(opt, in, K, Fs, center, fraction, cache, operator_s, ctx);

  sw.restart();
  const PatchGrower grower = prepare_patch_grower(m);
  const double prepare_s = sw.seconds();
  PatchWorkspace pws;
  SolveWorkspace ws;
  sw.restart();
  const PatchParam P = parameterize_patch(F, grower, center, patch_vertex_count(m.num_vertices(), fraction), pws, ws);
  const double query_s = sw.seconds();
  for (double v : P.uv)
    if (!std::isfinite(v)) fail(ErrorCode::Numerical, "param: the patch parameterization is not finite");

  if (!opt.output.empty()) {
    WriteOptions wo;
    wo.uv = &P.uv;
    write_mesh(opt.output, P.patch.mesh, wo);
    log_written(opt.output);
  }
  Json j{{"command", "param"}, {"input", input_json(opt, in)}};
  j["domain"] = "patch";
  j["boundary"] = "neumann";
  j["operator"] = "regularized cotan Laplacian of the whole mesh (-L_C + eps M), Neumann data of eq. 4.6";
  j["n"] = m.num_vertices();
  j["center"] = center;
  j["fraction"] = fraction;
  j["patch_vertices"] = P.patch.vertices.size();
  j["patch_faces"] = P.patch.faces.size();
  j["bfs_rings"] = P.patch.rings;
  j["boundary_vertices"] = P.boundary.size();
  j["boundary_loops"] = P.boundary_loops;
  j["euler_characteristic"] = P.euler_characteristic;
  j["flipped_faces"] = P.flips.flipped;
  j["degenerate_faces"] = P.flips.degenerate;
  j["orientation"] = P.flips.orientation;
  j["etree_height"] = sym->etree_height;
  j["forward_columns"] = P.forward_columns;
  j["backward_columns"] = P.backward_columns;
  j["factor_s"] = order_s + analyze_s + numeric_s;
  j["query_s"] = query_s;
  j["factor_cache"] = factor_cache_json(cache, Fs);
  j["timings"] = timings(in, {{"operator_s", operator_s},
                  {"order_s", order_s},    {"analyze_s", analyze_s},       {"numeric_s", numeric_s},
                  {"prepare_s", prepare_s}, {"grow_s", P.grow_s},          {"rhs_s", P.rhs_s},
                  {"solve_s", P.solve_s},  {"check_s", P.check_s}});
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": patch of " << P.patch.vertices.size() << " vertices around " << center
       << " (boundary " << P.boundary.size() << " vertices, " << P.boundary_loops << " loop(s), Euler characteristic "
       << P.euler_characteristic << ")\n  flipped faces " << P.flips.flipped << ", degenerate faces "
       << P.flips.degenerate << "\n  factor " << j["factor_s"] << " s, patch " << query_s << " s\n";
  });
  return 0;
}

}  // namespace locus::cli
