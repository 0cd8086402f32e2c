// `locus skinweights MESH --handles v1,v2+v3,... [--bone x0,y0,z0,x1,y1,z1 ...]
// [--exact] [--samples S] -o weights.ply`: per-vertex skinning weights from
// natural-neighbor coordinates of the handles (thesis §3.7.2); a client of
// locus::Session::skinning (engine/include/locus/engine/skinning_requests.hpp).
// A handle is a vertex, vertices joined by '+', or a bone (each --bone is one
// more handle, after --handles). Default by size: every vertex exact on a mesh
// of at most 10,000 vertices (method "exact"); the sampled method above that
// (exact rows at a vertex cover, propagated); on a clean mesh of more than
// 48,000 vertices a coarse level of the mesh (method "coarse",
// pipelines/.../skinning_coarse.hpp). --exact solves every vertex (slow on
// large meshes).
// -o writes the mesh with vertex properties w0..w{k-1} (PLY) in handle order.
// JSON: `handles`, `handle_vertices`, `method`, `samples`, `sample_rings`,
// `radius`, `coarse_vertices`, `degenerate_vertices`, `max_clamped`, `fallback_faces`, timings.
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "locus/engine/skinning_requests.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/site_args.hpp"

namespace locus::cli {
namespace {

struct SkinOptions {
  std::string handles_text;
  std::vector<std::string> bones;
  std::string t_text;
  bool exact = false;
  int32_t samples = 0;
};

// "4530,7448+7449,3233": one handle per comma, '+' joins the vertices of one handle.
std::vector<std::vector<int64_t>> parse_handles(const std::string& text, const Mesh& mesh) {
  std::vector<std::vector<int64_t>> handles;
  for (const std::string& part : split_commas(text)) {
    std::string joined = part;
    for (char& c : joined)
      if (c == '+') c = ',';
    const std::vector<int32_t> ids = parse_vertex_list("--handles", joined);
    vertex_sites(mesh, "--handles", ids);  // ids the file does not have: bad input (exit 3)
    handles.emplace_back(ids.begin(), ids.end());
  }
  return handles;
}

std::vector<double> parse_bone(const std::string& text) {
  const std::string msg = "--bone expects x,y,z of at least two points (x0,y0,z0,x1,y1,z1,...), got '" + text + "'";
  std::vector<double> xyz;
  for (const std::string& part : split_commas(text)) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      fail(ErrorCode::BadUsage, msg);
    }
    if (used != part.size() || !std::isfinite(v)) fail(ErrorCode::BadUsage, msg);
    xyz.push_back(v);
  }
  if (xyz.size() < 6 || xyz.size() % 3 != 0) fail(ErrorCode::BadUsage, msg);
  return xyz;
}

int run_skinweights(const CommonOptions& opt, const SkinOptions& o, const RunContext& ctx) {
  if (o.handles_text.empty() && o.bones.empty())
    fail(ErrorCode::BadUsage, "--handles is required (comma-separated vertex ids) unless --bone is given");
  if (o.samples < 0) fail(ErrorCode::BadUsage, "--samples must be >= 0");
  SkinningRequest req;
  for (const std::string& b : o.bones) req.bone.push_back(parse_bone(b));
  if (!o.t_text.empty()) parse_time_spec(o.t_text);  // bad usage before the mesh is read
  req.t = o.t_text;
  req.exact = o.exact;
  req.samples = o.samples;
  Input in = load_input(opt, ctx);
  const Mesh& mesh = in.mesh;
  if (!o.handles_text.empty()) req.handles = parse_handles(o.handles_text, mesh);
  const Session session{Mesh(mesh), session_options(in)};  // --operator (auto: robust on a defective mesh)
  RunContext run = ctx;
  const bool json = opt.json;
  run.progress = [json](double f, std::string_view phase) {
    if (!json) log(std::string(phase) + " " + std::to_string(static_cast<int>(100 * f + 0.5)) + "%");
  };
  const SkinningReport W = session.skinning(req, run);
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
  Json handles = Json::array();
  for (const auto& h : req.handles) handles.push_back(h.size() == 1 ? Json(h[0]) : Json(h));
  j["handles"] = handles;
  j["bones"] = req.bone;
  j["handle_vertices"] = W.handle_vertices;
  j["t"] = W.t;
  j["method"] = W.method;
  j["samples"] = W.samples;
  j["sample_rings"] = W.sample_rings;
  j["radius"] = W.radius;
  j["coarse_vertices"] = W.coarse_vertices;
  j["degenerate_vertices"] = W.degenerate_vertices;
  j["fallback_faces"] = W.fallback_faces;
  j["max_clamped"] = W.max_clamped;
  j["timings"] = timings(in, {{"factor_s", W.factor_s}, {"prepare_s", W.prepare_s}, {"weights_s", W.weights_s},
                              {"propagate_s", W.propagate_s}});
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": skinning weights (" << W.method << ") of " << k << " handles at " << n << " vertices in "
       << W.prepare_s + W.weights_s + W.propagate_s << " s" << (opt.output.empty() ? "" : " -> " + opt.output) << "\n";
  });
  return 0;
}

}  // namespace

void register_skinweights_command(CommandTable& table) {
  auto o = std::make_shared<SkinOptions>();
  CLI::App* app = table.add("skinweights", "Per-vertex skinning weights of handles (natural-neighbor coordinates)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_skinweights(opt, *o, ctx); });
  app->add_option("--handles", o->handles_text,
                  "Handles: comma-separated vertex ids; '+' joins the vertices of one handle (10+11+12,40)");
  app->add_option("--bone", o->bones, "A bone handle: x0,y0,z0,x1,y1,z1[,...] (its nearest vertices); repeatable")
      ->allow_extra_args(false);
  app->add_flag("--exact", o->exact, "Natural-neighbor coordinates at every vertex (slow: one heat solve per vertex)");
  app->add_option("--samples", o->samples, "Sampled method: at most this many exact sample vertices (default 1024)");
  app->add_option("--t", o->t_text, "Diffusion time: absolute or a multiple of h^2 (h2, 4h2); default h2")->check(non_empty());
}

}  // namespace locus::cli
