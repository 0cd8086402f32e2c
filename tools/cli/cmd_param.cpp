// `locus param MESH --method perfect|cotan|uniform -o uv.obj --json`: flip-free
// parameterization of a disk-like polygon mesh (thesis §2.6,
// pipelines/flipfree_param): boundary on the unit circle by arc length, interior
// from eq. 2.4 with perfect (Algorithm 1), cotan or uniform weights.
//
// -o FILE writes the input mesh with the parameterization as texture
// coordinates (OBJ `vt`, PLY u/v; OFF has none). JSON: method, flipped_faces,
// degenerate_faces, first_flipped_face, min_corner_sin, negative_weights,
// min_weight, and for perfect the iteration figures.
//
// Structure: options -> what to parameterize (a Domain) -> one solve per domain
// kind -> common checks and output. The whole mesh (a disk) is the only domain
// kind so far; a patch around a center vertex (--center V --fraction f) is a
// second Domain kind: add its options in register_param_command, its branch in
// parameterize(), and it reuses write/emit unchanged.
#include <ostream>

#include "locus/mesh_io.hpp"
#include "locus/pipelines/laplacian/flipfree_param.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/param_patch.hpp"

namespace locus::cli {
namespace {

struct ParamCliOptions {
  std::string method = "perfect";
  int iters = 1000;
  double eps = 1e-6;
  int center = -1;        // --center V: patch mode (tools/cli/param_patch.hpp)
  double fraction = 0.1;  // --fraction f of the vertices in the patch
  std::string boundary = "neumann";  // --boundary: patch mode's boundary data (param_patch.hpp)
  FactorCacheOptions cache;  // --save / --load: patch mode only (the disk methods refactor per iteration)
};

// What is parameterized.
enum class Domain { WholeDisk };

struct ParamRun {
  Domain domain = Domain::WholeDisk;
  FlipFreeParamResult result;
};

ParamRun parameterize(const Mesh& mesh, const ParamCliOptions& po, const RunContext& ctx) {
  FlipFreeParamOptions o;
  o.method = parse_param_method(po.method);
  o.iteration.max_iterations = po.iters;
  o.iteration.eps = po.eps;
  ParamRun run;
  run.domain = Domain::WholeDisk;
  run.result = flipfree_param(mesh, o, ctx);
  return run;
}

int run_param(const CommonOptions& opt, const ParamCliOptions& po, const RunContext& ctx) {
  check_uv_output(opt, "param");
  if (po.center >= 0) return run_param_patch(opt, po.center, po.fraction, po.boundary, po.cache, ctx);
  if (po.boundary != "neumann")
    fail(ErrorCode::BadUsage, "param: --boundary applies to the patch mode (--center V)");
  if (!po.cache.save.empty() || !po.cache.load.empty())
    fail(ErrorCode::BadUsage, "param: --save / --load apply to the patch mode (--center V); the disk methods "
                              "factor a new matrix per iteration");
  parse_param_method(po.method);  // bad usage before reading the file
  Input in = load_input(opt, ctx, PolygonFaces::Keep);
  const ParamRun run = parameterize(in.mesh, po, ctx);
  const FlipFreeParamResult& r = run.result;
  if (!opt.output.empty()) {
    WriteOptions wo = carried_attributes(in, false, /*result_uv=*/true);
    wo.uv = &r.uv;
    write_mesh(opt.output, in.mesh, wo);
  }
  Json j{{"command", "param"}, {"input", input_json(opt, in)}};
  j["domain"] = "disk";
  j["method"] = po.method;
  j["flipped_faces"] = r.faces.flipped_faces;
  j["degenerate_faces"] = r.faces.degenerate_faces;
  j["first_flipped_face"] = r.faces.first_flipped;
  j["min_corner_sin"] = r.faces.min_corner_sin;
  j["negative_weights"] = r.negative_weights;
  j["min_weight"] = r.min_weight;
  if (po.method == "perfect") {
    j["converged"] = r.converged;
    j["iterations"] = r.iterations;
    j["zero_weights"] = r.zero_weights;
    j["first_iter_s"] = r.first_iter_s;
    j["iter_s"] = r.iter_s;
  }
  j["timings"] = timings(in, {{"param_s", r.total_s}});
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": " << po.method << " parameterization\n  flipped faces " << r.faces.flipped_faces
       << ", degenerate faces " << r.faces.degenerate_faces << ", negative weights " << r.negative_weights << "\n";
    if (po.method == "perfect")
      os << "  Algorithm 1: " << (r.converged ? "converged" : "NOT converged") << " after " << r.iterations
         << " iterations\n";
  });
  return 0;
}

}  // namespace

void register_param_command(CommandTable& table) {
  auto po = std::make_shared<ParamCliOptions>();
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
  add_factor_cache_options(app, po->cache);
}

}  // namespace locus::cli
