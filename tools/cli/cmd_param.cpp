// `locus param MESH --method perfect|cotan|uniform -o uv.obj --json`: flip-free
// parameterization of a disk-like polygon mesh (thesis §2.6): boundary on the unit circle by arc length, interior
// from eq. 2.4 with perfect (Algorithm 1), cotan or uniform weights.
//
// -o FILE writes the input mesh with the parameterization as texture
// coordinates (OBJ `vt`, PLY u/v; OFF has none). JSON: method, flipped_faces,
// degenerate_faces, first_flipped_face, min_corner_sin, negative_weights,
// min_weight, and for perfect the iteration figures.
//
// Both domains are computed by locus::Session::param (engine/include/locus/
// engine/param_request.hpp), which owns the checks; the patch mode's output
// is cmd_param_patch.cpp's.
#include <ostream>

#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/param_patch.hpp"

namespace locus::cli {
namespace {

Json disk_json(const CommonOptions& opt, const Input& in, const ParamRequest& q, const ParamReport& r) {
  Json j{{"command", "param"}, {"input", input_json(opt, in)}};
  j["domain"] = "disk";
  j["method"] = q.method;
  j["flipped_faces"] = r.flipped_faces;
  j["degenerate_faces"] = r.degenerate_faces;
  j["first_flipped_face"] = r.first_flipped_face;
  j["min_corner_sin"] = r.min_corner_sin;
  j["negative_weights"] = r.negative_weights;
  j["min_weight"] = r.min_weight;
  if (q.method == "perfect") {
    j["converged"] = r.converged;
    j["iterations"] = r.iterations;
    j["zero_weights"] = r.zero_weights;
    j["first_iter_s"] = r.first_iter_s;
    j["iter_s"] = r.iter_s;
  }
  j["timings"] = timings(in, {{"param_s", r.param_s}});
  return j;
}

int run_param(const CommonOptions& opt, const ParamRequest& q, const RunContext& ctx) {
  check_uv_output(opt, "param");
  if (q.center >= 0) return run_param_patch(opt, q, ctx);
  check_request(q);  // bad usage before reading the file
  const Input in = load_input(opt, ctx, PolygonFaces::Keep);
  const Session session{Mesh(in.mesh), session_options(in)};
  const ParamReport r = session.param(q, ctx);
  if (!opt.output.empty()) {
    WriteOptions wo = carried_attributes(in, false, /*result_uv=*/true);
    wo.uv = &r.uv;
    write_mesh(opt.output, in.mesh, wo);
  }
  emit(opt, disk_json(opt, in, q, r), [&](std::ostream& os) {
    os << opt.mesh_path << ": " << q.method << " parameterization\n  flipped faces " << r.flipped_faces
       << ", degenerate faces " << r.degenerate_faces << ", negative weights " << r.negative_weights << "\n";
    if (q.method == "perfect")
      os << "  Algorithm 1: " << (r.converged ? "converged" : "NOT converged") << " after " << r.iterations
         << " iterations\n";
  });
  return 0;
}

}  // namespace

void register_param_command(CommandTable& table) {
  auto po = std::make_shared<ParamRequest>();
  CLI::App* app = table.add("param", "Flip-free parameterization of a disk (thesis 2.6): perfect, cotan or uniform weights",
                            [po](const CommonOptions& opt, const RunContext& ctx) { return run_param(opt, *po, ctx); });
  app->add_option("--method", po->method, "perfect (Algorithm 1), cotan or uniform (default perfect)");
  app->add_option("--iters", po->iters, "Algorithm 1 iteration cap (default 1000)")->check(CLI::Range(1, 1000000));
  app->add_option("--eps", po->eps, "Algorithm 1 tolerance (default 1e-6 of the diagonal)")->check(CLI::PositiveNumber);
  app->add_option("--center", po->center, "Patch mode: BFS patch around vertex V, parameterized from the global factor (thesis 4.4)")
      ->check(CLI::Range(0, 2147483647));
  app->add_option("--fraction", po->fraction, "Patch mode: fraction of the vertices in the patch (default 0.1)");
  app->add_option("--boundary", po->boundary,
                  "Patch mode: neumann (eq. 4.6 on the global factor, default) or circle (boundary fixed on a "
                  "circle, factor of the patch by the factor-once update; flip-free on disk patches with "
                  "positive weights)");
  add_factor_cache_options(app, po->save, po->load);
}

}  // namespace locus::cli
