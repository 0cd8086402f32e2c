// `locus hks MESH --ts t1,t2,... (--vertices LIST | --all) [--method subset|selinv|full] [-o out.ply] --json`:
// the heat kernel signature of thesis §4.6 — the auto-diffusion values
// (M - t L_C)^{-1}_ii for several t (no mass scaling) — with one ordering and
// one symbolic factor shared by every t; a client of locus::Session::hks /
// adf (engine/include/locus/engine/diffusion_requests.hpp), which own the
// validation and the computation. Also the body of `locus adf` (cmd_adf.cpp),
// which is the same with one t.
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
#include <limits>
#include <ostream>
#include <utility>

#include "locus/io/file_extension.hpp"
#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tools/cli/heat_signature.hpp"
#include "tools/cli/vertex_list.hpp"
#include "tools/cli/written_files.hpp"

namespace locus::cli {

namespace {

using Previews = std::vector<std::pair<size_t, std::string>>;

// (index of t, file) of every preview image: one file for adf, a single t or
// --preview-t; otherwise FILE-tK.png per t.
Previews preview_files(const HeatSignatureCli& so, size_t nt) {
  Previews out;
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

// The request's fields from the texts of the command line, then the usage
// errors: the request's own (the Session's checks) and the CLI's (-o, --preview).
Previews check_usage(const CommonOptions& opt, HeatSignatureCli& so) {
  const std::string& command = so.command;
  const bool adf = command == "adf";
  const std::vector<int64_t> ids = so.vertices.empty() ? std::vector<int64_t>{} : parse_vertex_ids(so.vertices, "--vertices");
  if (adf) {
    so.adf.vertices = ids;
    check_request(so.adf);
  } else {
    so.hks.ts = split_list(so.ts, "--ts");
    so.hks.vertices = ids;
    check_request(so.hks);
  }
  const bool all = adf ? so.adf.all : so.hks.all;
  const size_t nt = adf ? 1 : so.hks.ts.size();
  if (!opt.output.empty() && !all)
    fail(ErrorCode::BadUsage, command + ": -o writes a value for every vertex; use it with --all (with --vertices the "
                                        "values are in the JSON)");
  if (!opt.output.empty() && io::lower_extension(opt.output) == "off" && nt > 1)
    fail(ErrorCode::BadUsage, command + ": -o " + opt.output + ": OFF shows one value per vertex (as colours), not " +
                                  std::to_string(nt) + " diffusion times; use .ply or .obj");
  check_preview_options(so.preview);
  if (!so.preview.path.empty() && !all)
    fail(ErrorCode::BadUsage, command + ": --preview shows a value at every vertex; use it with --all");
  if (so.preview_t >= static_cast<int>(nt))
    fail(ErrorCode::BadUsage, command + ": --preview-t " + std::to_string(so.preview_t) + ": there are " +
                                  std::to_string(nt) + " times in --ts (0.." + std::to_string(nt - 1) + ")");
  if (so.preview_t >= 0 && so.preview.path.empty())
    fail(ErrorCode::BadUsage, command + ": --preview-t chooses the t of --preview FILE.png; give --preview too");
  const Previews previews = preview_files(so, nt);
  for (const auto& [t, path] : previews) check_preview_path(path);
  return previews;
}

std::string property_name(const std::string& command, size_t t) {
  return command == "adf" ? std::string("adf") : "hks_" + std::to_string(t);
}

std::vector<double> values_at(const HeatSignatureReport& r, size_t t) {
  const size_t nt = r.t.size(), count = r.count();
  std::vector<double> v(count);
  for (size_t k = 0; k < count; ++k) v[k] = r.values[k * nt + t];
  return v;
}

void write_values(const CommonOptions& opt, const Input& in, const std::string& command, const HeatSignatureReport& r) {
  if (opt.output.empty()) return;
  WriteOptions wo = carried_attributes(in);
  for (size_t j = 0; j < r.t.size(); ++j)
    add_result(wo, {property_name(command, j), VertexProperty::Type::Double, values_at(r, j)});
  write_mesh(opt.output, output_faces(in), wo);
  log_written(opt.output);
}

Json values_json(const std::string& command, const HeatSignatureReport& r) {
  const size_t nt = r.t.size(), count = r.count();
  Json j;
  if (r.all) {
    Json summary = Json::array();
    for (size_t t = 0; t < nt; ++t) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
      size_t valued = 0;  // NaN: an unreferenced vertex (no value)
      for (double v : values_at(r, t))
        if (!std::isnan(v)) lo = std::min(lo, v), hi = std::max(hi, v), sum += v, ++valued;
      summary.push_back({{"t", r.t[t]}, {"min", lo}, {"max", hi}, {"mean", sum / static_cast<double>(valued)}});
    }
    j["summary"] = summary;
    return j;
  }
  j["vertices"] = r.vertices;
  if (command == "adf") {
    j["adf"] = r.values;
    return j;
  }
  Json rows = Json::array();
  for (size_t k = 0; k < count; ++k)
    rows.push_back(std::vector<double>(r.values.begin() + static_cast<std::ptrdiff_t>(k * nt),
                                       r.values.begin() + static_cast<std::ptrdiff_t>((k + 1) * nt)));
  j["hks"] = rows;
  return j;
}

Json signature_json(const CommonOptions& opt, const Input& in, const std::string& command,
                    const HeatSignatureReport& r) {
  Json j{{"command", command}, {"input", input_json(opt, in)}};
  j["quantity"] = "(M - t L_C)^{-1}_ii: heat at vertex i after one backward-Euler step from a unit amount at i "
                  "(eq. 6.3, b = e_i); multiply by M_ii for a unit density";
  j["method"] = r.method;
  j["n"] = r.n;
  j["h"] = r.h;
  if (command == "adf") {
    j["t"] = r.t[0];
    j["t_spec"] = r.t_spec[0];
  } else {
    j["t"] = r.t;
    j["t_spec"] = r.t_spec;
  }
  j["threads"] = threads_used(opt);
  j["nnz_L"] = r.nnz_L;
  j["supernodes"] = r.supernodes;
  j["etree_height"] = r.etree_height;
  j["factor_s"] = r.factor_s();
  j["query_s"] = r.query_s;
  j["evaluated"] = r.count();
  j.update(values_json(command, r));
  if (r.all && !opt.output.empty()) j["output"] = opt.output;
  j["factor_cache"] = factor_cache_json(r.factor_cache);
  j["timings"] = timings(in, {{"operator_s", r.operator_s},
                              {"order_s", r.order_s},
                              {"analyze_s", r.analyze_s},
                              {"numeric_s", r.numeric_s}});
  return j;
}

Json write_previews(const Input& in, const HeatSignatureCli& so, const Previews& previews,
                    const HeatSignatureReport& r) {
  Json files = Json::array();
  const size_t nt = r.t.size();
  for (const auto& [t, path] : previews) {
    write_preview(in.mesh, values_at(r, t), PreviewKind::Scalar, so.preview,
                  {property_name(so.command, t) + " = (M - tL)^-1_ii at t = " + format_number(r.t[t]) + " (" +
                       r.t_spec[t] + ")" + (nt > 1 ? ", t " + std::to_string(t + 1) + " of " + std::to_string(nt) : ""),
                   {}, "", false, /*clip=*/0.01},
                  path);
    files.push_back(path);
  }
  return files.size() == 1 ? files[0] : files;
}

}  // namespace

void add_heat_signature_options(CLI::App* app, HeatSignatureCli& so) {
  const bool adf = so.command == "adf";
  app->add_option("--vertices", so.vertices, "Comma-separated vertex ids to evaluate (values go to the JSON)");
  app->add_flag("--all", adf ? so.adf.all : so.hks.all, "Evaluate every vertex (needed for -o)");
  app->add_option("--method", adf ? so.adf.method : so.hks.method,
                  "subset (etree path per vertex, default), selinv (selected inversion, all vertices at once) or full "
                  "(one full solve per vertex; slow reference)")
      ->check(CLI::IsMember({"subset", "selinv", "full"}));
  add_factor_cache_options(app, adf ? so.adf.save : so.hks.save, adf ? so.adf.load : so.hks.load);
  add_preview_option(app, so.preview);
}

int run_heat_signature(const CommonOptions& opt, HeatSignatureCli& so, const RunContext& ctx) {
  const Previews previews = check_usage(opt, so);
  const bool adf = so.command == "adf";
  const Input in = load_input(opt, ctx);
  check_file_vertices(adf ? so.adf.vertices : so.hks.vertices, in.mesh.num_vertices(), "--vertices");
  const Session session{Mesh(in.mesh), session_options(in)};
  const HeatSignatureReport r = adf ? session.adf(so.adf, ctx) : session.hks(so.hks, ctx);
  write_values(opt, in, so.command, r);
  Json j = signature_json(opt, in, so.command, r);
  if (!previews.empty()) j["preview"] = write_previews(in, so, previews, r);
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": " << so.command << " by " << r.method << ", n " << r.n << ", etree height "
       << r.etree_height << "\n  factor " << r.factor_s() << " s (" << r.t.size() << " t), values " << r.query_s
       << " s for " << r.count() << " vertices\n";
    if (!r.all)
      for (size_t k = 0; k < r.count(); ++k) {
        os << "  vertex " << r.vertices[k] << ":";
        for (size_t t = 0; t < r.t.size(); ++t) os << " " << r.values[k * r.t.size() + t];
        os << "\n";
      }
  });
  return 0;
}

void register_hks_command(CommandTable& table) {
  auto so = std::make_shared<HeatSignatureCli>();
  so->command = "hks";
  CLI::App* app = table.add("hks", "Heat kernel signature (thesis 4.6): (M - tL)^{-1}_ii for several t",
                            [so](const CommonOptions& opt, const RunContext& ctx) {
                              return run_heat_signature(opt, *so, ctx);
                            });
  app->add_option("--ts", so->ts,
                  "Comma-separated diffusion times: absolute (1e-3) or multiples of h^2 (1h2,10h2,100h2)")
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
