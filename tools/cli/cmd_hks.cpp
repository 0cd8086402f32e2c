// `locus hks MESH --ts t1,t2,... (--vertices LIST | --all) [--method subset|selinv|full] [-o out.ply] --json`:
// the heat kernel signature of thesis §4.6 — the auto-diffusion values
// (M - t L_C)^{-1}_ii for several t (no mass scaling; see pipelines/include/locus/pipelines/heat/adf.hpp) —
// with one ordering and one symbolic factor shared by every t. Also the body of
// `locus adf` (cmd_adf.cpp), which is the same with one t.
//
// Output file: only with --all (every vertex has a value, so the file has no
// placeholders): the input mesh as PLY with vertex properties `adf` (adf) or
// hks_0, hks_1, ... in the order of --ts (hks). With --vertices the values are
// in the JSON only, and -o is a usage error.
// JSON: n, factor_s (ordering + symbolic + numeric for every t), query_s (the
// values after factorization), the method, t (absolute) and the t as given,
// the factor's size and etree height; per-vertex values for --vertices, or
// min / max / mean per t for --all.
// --save F / --load F keep the factors (one per t) in a factor cache;
// --preview out.png (with --all) renders the values: adf and a single t into
// out.png, several t into out-t0.png, out-t1.png, ... (in the order of --ts,
// as the properties hks_0, hks_1, ...), or only the K-th with --preview-t K.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <ostream>
#include <utility>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/io/file_extension.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/heat/adf.hpp"
#include "tools/cli/heat_signature.hpp"
#include "tools/cli/written_files.hpp"
#include "tools/cli/vertex_list.hpp"

namespace locus::cli {

namespace {

// (index of t, file) of every preview image: one file for adf, a single t or
// --preview-t; otherwise FILE-tK.png per t.
std::vector<std::pair<size_t, std::string>> preview_files(const HeatSignatureCliOptions& so, size_t nt) {
  std::vector<std::pair<size_t, std::string>> out;
  if (so.preview.path.empty()) return out;
  if (so.preview_t >= 0) {
    out.emplace_back(static_cast<size_t>(so.preview_t), so.preview.path);
  } else if (nt == 1) {
    out.emplace_back(0, so.preview.path);
  } else {
    for (size_t t = 0; t < nt; ++t) out.emplace_back(t, preview_path_with(so.preview.path, "-t" + std::to_string(t)));
  }
  return out;
}

}  // namespace

void add_heat_signature_options(CLI::App* app, HeatSignatureCliOptions& so) {
  app->add_option("--vertices", so.vertices, "Comma-separated vertex ids to evaluate (values go to the JSON)");
  app->add_flag("--all", so.all, "Evaluate every vertex (needed for -o)");
  app->add_option("--method", so.method,
                  "subset (etree path per vertex, default), selinv (selected inversion, all vertices at once) or full "
                  "(one full solve per vertex; slow reference)")
      ->check(CLI::IsMember({"subset", "selinv", "full"}));
  add_factor_cache_options(app, so.cache);
  add_preview_option(app, so.preview);
}

int run_heat_signature(const std::string& command, const CommonOptions& opt, const HeatSignatureCliOptions& so,
                       const RunContext& ctx) {
  // Usage errors before reading the file.
  const AdfMethod method = parse_adf_method(so.method);
  std::vector<TimeSpec> specs;
  for (const std::string& s : so.t_texts) specs.push_back(parse_time_spec(s));
  if (specs.empty()) fail(ErrorCode::BadUsage, command + ": no diffusion time given");
  if (so.all == !so.vertices.empty()) fail(ErrorCode::BadUsage, command + ": give exactly one of --vertices LIST or --all");
  if (!opt.output.empty() && !so.all)
    fail(ErrorCode::BadUsage, command + ": -o writes a value for every vertex; use it with --all (with --vertices the "
                                        "values are in the JSON)");
  if (!opt.output.empty() && io::lower_extension(opt.output) == "off" && specs.size() > 1)
    fail(ErrorCode::BadUsage, command + ": -o " + opt.output + ": OFF shows one value per vertex (as colours), not " +
                                  std::to_string(specs.size()) + " diffusion times; use .ply or .obj");
  validate_factor_cache_options(so.cache);
  check_preview_options(so.preview);
  if (!so.preview.path.empty() && !so.all)
    fail(ErrorCode::BadUsage, command + ": --preview shows a value at every vertex; use it with --all");
  if (so.preview_t >= static_cast<int>(specs.size()))
    fail(ErrorCode::BadUsage, command + ": --preview-t " + std::to_string(so.preview_t) + ": there are " +
                                  std::to_string(specs.size()) + " times in --ts (0.." + std::to_string(specs.size() - 1) + ")");
  if (so.preview_t >= 0 && so.preview.path.empty())
    fail(ErrorCode::BadUsage, command + ": --preview-t chooses the t of --preview FILE.png; give --preview too");
  const std::vector<std::pair<size_t, std::string>> previews = preview_files(so, specs.size());
  for (const auto& [t, path] : previews) check_preview_path(path);

  Input in = load_input(opt, ctx);
  const Mesh& m = in.mesh;
  const std::string where = m.source.empty() ? std::string("the mesh") : m.source;
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, where + " has no faces");
  check_input_operator(in);
  const double h = mean_edge_length(m);
  if (!(h > 0) || !std::isfinite(h)) fail(ErrorCode::BadInput, where + ": mean edge length is " + format_number(h));
  std::vector<double> ts;
  for (const TimeSpec& s : specs) ts.push_back(s.resolve(h));
  const std::vector<int32_t> vertices = so.all ? std::vector<int32_t>{} : parse_vertex_list(so.vertices, m.num_vertices(), "--vertices");
  ctx.check_cancel();

  // One heat operator per t on one pattern: factored (one ordering, one symbolic factor) or loaded.
  HeatFactors H;
  H.t = ts;
  Stopwatch osw;
  std::vector<CscMatrix> A;
  for (double t : ts) {
    if (!(std::isfinite(t) && t > 0))
      fail(ErrorCode::BadUsage, command + ": diffusion time " + format_number(t) + " must be finite and > 0");
    A.push_back(input_heat_operator(in, t));
  }
  H.operator_s = osw.seconds();
  std::vector<FactorRequest> req;
  for (size_t k = 0; k < ts.size(); ++k) req.push_back({"heat", ts[k], &A[k]});
  Factors F = factor_or_load(so.cache, m, req, ctx);
  H.symbolic = F.symbolic;
  H.factors = std::move(F.factors);
  H.order_s = F.order_s;
  H.analyze_s = F.analyze_s;
  H.numeric_s = F.numeric_s;
  const double factor_s = H.order_s + H.analyze_s + H.numeric_s;
  const size_t nt = ts.size();
  const size_t count = so.all ? static_cast<size_t>(m.num_vertices()) : vertices.size();
  std::vector<double> values(count * nt);
  Stopwatch sw;
  heat_kernel_signature(H, vertices, method, values, ctx);
  const double query_s = sw.seconds();
  for (size_t k = 0; k < values.size(); ++k)
    if (!(std::isfinite(values[k]) && values[k] > 0)) {
      const int32_t v = so.all ? static_cast<int32_t>(k / nt) : vertices[k / nt];
      fail(ErrorCode::Numerical, command + ": the value at vertex " + std::to_string(v) + " for t = " +
                                     format_number(ts[k % nt]) + " is " + format_number(values[k]) +
                                     "; the heat operator is numerically singular");
    }

  if (!opt.output.empty()) {
    WriteOptions wo = carried_attributes(in);
    for (size_t j = 0; j < nt; ++j) {
      VertexProperty p;
      p.name = command == "adf" ? std::string("adf") : "hks_" + std::to_string(j);
      p.type = VertexProperty::Type::Double;
      p.values.resize(count);
      for (size_t k = 0; k < count; ++k) p.values[k] = values[k * nt + j];
      add_result(wo, std::move(p));
    }
    write_mesh(opt.output, output_faces(in), wo);
    log_written(opt.output);
  }

  Json j{{"command", command}, {"input", input_json(opt, in)}};
  j["quantity"] = "(M - t L_C)^{-1}_ii: heat at vertex i after one backward-Euler step from a unit amount at i "
                  "(eq. 6.3, b = e_i); multiply by M_ii for a unit density";
  j["method"] = adf_method_name(method);
  j["n"] = m.num_vertices();
  j["h"] = h;
  if (command == "adf") {
    j["t"] = ts[0];
    j["t_spec"] = so.t_texts[0];
  } else {
    j["t"] = ts;
    j["t_spec"] = so.t_texts;
  }
  j["threads"] = threads_used(opt);
  j["nnz_L"] = H.symbolic->nnz_L;
  j["supernodes"] = H.symbolic->ns;
  j["etree_height"] = H.symbolic->etree_height;
  j["factor_s"] = factor_s;
  j["query_s"] = query_s;
  j["evaluated"] = count;
  if (so.all) {
    Json summary = Json::array();
    for (size_t t = 0; t < nt; ++t) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
      for (size_t k = 0; k < count; ++k) {
        const double v = values[k * nt + t];
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        sum += v;
      }
      summary.push_back({{"t", ts[t]}, {"min", lo}, {"max", hi}, {"mean", sum / static_cast<double>(count)}});
    }
    j["summary"] = summary;
    if (!opt.output.empty()) j["output"] = opt.output;
  } else {
    j["vertices"] = vertices;
    if (command == "adf") {
      j["adf"] = values;
    } else {
      Json rows = Json::array();
      for (size_t k = 0; k < count; ++k)
        rows.push_back(std::vector<double>(values.begin() + static_cast<std::ptrdiff_t>(k * nt),
                                           values.begin() + static_cast<std::ptrdiff_t>((k + 1) * nt)));
      j["hks"] = rows;
    }
  }
  j["factor_cache"] = factor_cache_json(so.cache, F);
  j["timings"] = timings(in, {{"operator_s", H.operator_s},
                  {"order_s", H.order_s}, {"analyze_s", H.analyze_s}, {"numeric_s", H.numeric_s}});
  if (!previews.empty()) {
    Json files = Json::array();
    for (const auto& [t, path] : previews) {
      std::vector<double> shown(count);
      for (size_t k = 0; k < count; ++k) shown[k] = values[k * nt + t];
      const std::string name = command == "adf" ? std::string("adf") : "hks_" + std::to_string(t);
      write_preview(m, shown, PreviewKind::Scalar, so.preview,
                    {name + " = (M - tL)^-1_ii at t = " + format_number(ts[t]) + " (" + so.t_texts[t] + ")" +
                         (nt > 1 ? ", t " + std::to_string(t + 1) + " of " + std::to_string(nt) : ""),
                     {}, "", false, /*clip=*/0.01},
                    path);
      files.push_back(path);
    }
    j["preview"] = files.size() == 1 ? files[0] : files;
  }
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": " << command << " by " << adf_method_name(method) << ", n " << m.num_vertices()
       << ", etree height " << H.symbolic->etree_height << "\n  factor " << factor_s << " s (" << nt
       << " t), values " << query_s << " s for " << count << " vertices\n";
    if (!so.all)
      for (size_t k = 0; k < count; ++k) {
        os << "  vertex " << vertices[k] << ":";
        for (size_t t = 0; t < nt; ++t) os << " " << values[k * nt + t];
        os << "\n";
      }
  });
  return 0;
}

void register_hks_command(CommandTable& table) {
  auto so = std::make_shared<HeatSignatureCliOptions>();
  auto ts = std::make_shared<std::string>();
  CLI::App* app = table.add("hks", "Heat kernel signature (thesis 4.6): (M - tL)^{-1}_ii for several t",
                            [so, ts](const CommonOptions& opt, const RunContext& ctx) {
                              so->t_texts = split_list(*ts, "--ts");
                              return run_heat_signature("hks", opt, *so, ctx);
                            });
  app->add_option("--ts", *ts, "Comma-separated diffusion times: absolute (1e-3) or multiples of h^2 (1h2,10h2,100h2)")
      ->required();
  add_heat_signature_options(app, *so);
  app->add_option("--preview-t", so->preview_t,
                  "With --preview: only the K-th time of --ts (0-based, as hks_K) into FILE.png (default: every t, "
                  "FILE-t0.png, FILE-t1.png, ...)")
      ->check(CLI::Range(0, 1 << 20));
}

void register_local_solve_commands(CommandTable& table) {
  register_adf_command(table);
  register_hks_command(table);
  register_heat_command(table);
}

}  // namespace locus::cli
