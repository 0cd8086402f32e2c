// `locus skinweights MESH --handles v1,v2,... -o weights.ply`: per-vertex skinning
// weights from natural-neighbor coordinates of the handle set (thesis §3.7.2;
// pipelines/include/locus/pipelines/voronoi/skinning_weights.hpp). -o writes the mesh with vertex properties
// w0..w{k-1} (PLY) in --handles order. JSON: `handles`, `degenerate_vertices`,
// `max_clamped`, `fallback_faces`, timings.
#include <ostream>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/site_args.hpp"

namespace locus::cli {
namespace {

struct SkinOptions {
  std::string handles_text;
  std::string t_text;
  bool exact = false;
  int32_t samples = 0;
};

int run_skinweights(const CommonOptions& opt, const SkinOptions& o, const RunContext& ctx) {
  if (o.handles_text.empty()) fail(ErrorCode::BadUsage, "--handles is required (comma-separated vertex ids)");
  const std::vector<int32_t> ids = parse_vertex_list("--handles", o.handles_text);
  if (o.samples < 0) fail(ErrorCode::BadUsage, "--samples must be >= 0");
  const TimeSpec ts = o.t_text.empty() ? TimeSpec{} : parse_time_spec(o.t_text);
  Input in = load_input(opt, ctx);
  const Mesh& mesh = in.mesh;
  vertex_sites(mesh, "--handles", ids);  // range check with the option's name
  std::vector<std::vector<int32_t>> handles;
  for (int32_t v : ids) handles.push_back({v});
  Stopwatch sw;
  const HeatDiffusion H = ts.times_h2 ? prepare_heat_diffusion(mesh, ts.value, 0.0, ctx)
                                      : prepare_heat_diffusion(mesh, 1.0, ts.value, ctx);
  const double factor_s = sw.seconds();
  RunContext run = ctx;
  const bool json = opt.json;
  run.progress = [json](double f, std::string_view phase) {
    if (!json) log(std::string(phase) + " " + std::to_string(static_cast<int>(100 * f + 0.5)) + "%");
  };
  SkinningOptions so;
  so.method = o.exact ? SkinningMethod::Exact : SkinningMethod::Sampled;
  so.samples = o.samples;
  const SkinningWeights W = skinning_weights(H, mesh, handles, so, run);
  const int32_t n = mesh.num_vertices(), k = W.handles;
  if (!opt.output.empty()) {
    WriteOptions wo = carried_attributes(in);
    for (int32_t j = 0; j < k; ++j) {
      std::vector<double> col(n);
      for (int32_t v = 0; v < n; ++v) col[v] = W.weight[static_cast<size_t>(v) * k + j];
      add_result(wo, {"w" + std::to_string(j), VertexProperty::Type::Double, std::move(col)});
    }
    write_mesh(opt.output, output_faces(in), wo);
  }
  Json j{{"command", "skinweights"}, {"input", input_json(opt, in)}};
  j["n"] = n;
  j["handles"] = ids;
  j["t"] = H.t;
  j["degenerate_vertices"] = W.degenerate;
  j["fallback_faces"] = W.fallback_faces;
  j["max_clamped"] = W.max_clamped;
  j["method"] = W.method;
  j["samples"] = W.samples;
  j["sample_rings"] = W.sample_rings;
  j["radius"] = W.radius;
  j["timings"] = timings(in, {{"factor_s", factor_s}, {"prepare_s", W.prepare_s}, {"weights_s", W.weights_s}, {"propagate_s", W.propagate_s}});
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": skinning weights of " << k << " handles at " << n << " vertices in " << W.weights_s
       << " s" << (opt.output.empty() ? "" : " -> " + opt.output) << "\n";
  });
  return 0;
}

}  // namespace

void register_skinweights_command(CommandTable& table) {
  auto o = std::make_shared<SkinOptions>();
  CLI::App* app = table.add("skinweights", "Per-vertex skinning weights of vertex handles (natural-neighbor coordinates)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_skinweights(opt, *o, ctx); });
  app->add_option("--handles", o->handles_text, "Handles: comma-separated vertex ids");
  app->add_flag("--exact", o->exact, "Natural-neighbor coordinates at every vertex (slow: n heat solves)");
  app->add_option("--samples", o->samples, "Sampled method: about this many exact sample vertices (default 1024)");
  app->add_option("--t", o->t_text, "Diffusion time: absolute or a multiple of h^2 (h2, 4h2); default h2")->check(non_empty());
}

}  // namespace locus::cli
