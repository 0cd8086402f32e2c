// The shared grammar and helpers of the locus tools (see cli_common.hpp):
// parsing, exit statuses, the SIGINT cancel flag, the thread budget, loading
// and subdividing the input, JSON output, --t / --operator parsing.
#include "tools/cli/cli_common.hpp"
#include "tools/cli/written_files.hpp"

#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <new>
#include <optional>

#include "locus/io/atomic_file_write.hpp"
#include "locus/kernels/factor/memory_budget.hpp"
#include "locus/io/factor_cache.hpp"
#include "locus/io/file_extension.hpp"
#include "locus/io/write_png.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/subdivision_budget.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/polygon_triangulation.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/render/rasterize.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "locus/locus.h"
#include "locus/mesh_io.hpp"

namespace locus::cli {
namespace {

// Raised by SIGINT, read by every RunContext the tools create. A lock-free
// atomic store is async-signal-safe; the handler then restores the default
// action so that a second Ctrl-C kills a run that does not stop promptly.
std::atomic<bool> g_cancel{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_sigint(int) {
  g_cancel.store(true, std::memory_order_relaxed);
  std::signal(SIGINT, SIG_DFL);
}

std::string g_tool = "locus";

// Preview images this command wrote (write_preview), for the JSON key `preview`.
std::vector<std::string> g_previews;

// Files the command staged (log_written), logged once they are committed.
std::vector<std::string> g_written;

// For the `timings` every command reports: when the command started, and the
// input's load and subdivision times (load_input).
Stopwatch g_command_clock;
double g_load_s = 0, g_subdivide_s = 0;

}  // namespace

struct CommandTable::Command {
  std::string name;
  CLI::App* app = nullptr;
  CommonOptions common;
  CommandBody body;
};

CommandTable::CommandTable(std::string tool_name, std::string description)
    : tool_(std::move(tool_name)), app_(std::move(description), tool_) {
  app_.set_version_flag("--version", std::string(tool_) + " " + locus_version(nullptr, nullptr, nullptr));
  app_.require_subcommand(1);
  app_.fallthrough(false);
  app_.footer("Usage: " + tool_ + " <command> <mesh-file> [options]; '" + tool_ +
              " <command> --help' lists a command's options.\n"
              "Exit status: 0 ok, 2 bad usage, 3 bad input file, 4 numerical failure, 5 cancelled (SIGINT).");
}

CommandTable::~CommandTable() = default;

CLI::App* CommandTable::add(const std::string& name, const std::string& description, CommandBody body) {
  auto cmd = std::make_unique<Command>();
  cmd->name = name;
  cmd->body = std::move(body);
  CLI::App* app = app_.add_subcommand(name, description);
  CommonOptions& c = cmd->common;
  app->add_option("mesh-file", c.mesh_path, "Input mesh (.off .obj .ply)")->required();
  app->add_flag("--json", c.json, "Print one JSON object on stdout (logs go to stderr)");
  app->add_option("-o,--output", c.output,
                  "Result file; the format follows the extension: .ply (named vertex properties), .obj (properties "
                  "in a '#vp' comment block, UVs as vt), .off (the first property as vertex colours)")
      ->check(output_file({"ply", "obj", "off"}));
  app->add_option("--threads", c.threads, "Worker threads (default 0: all cores)")->check(CLI::Range(0, 4096));
  app->add_option("--seed", c.seed, "Seed of every random choice (default 1)");
  app->add_option("--subdivide", c.subdivide, "1:4 midpoint subdivision K times after loading")
      ->check(CLI::Range(0, 16));
  app->add_option("--max-memory", c.max_memory,
                  "Memory limit of a subdivision or factorization: bytes or K/M/G/T (e.g. 4G); default 80% of physical memory");
  cmd->app = app;
  commands_.push_back(std::move(cmd));
  return app;
}

void CommandTable::add_listing(const std::string& name, const std::string& description) {
  app_.add_subcommand(name, description)->allow_extras()->prefix_command();
}

std::vector<std::string> CommandTable::names() const {
  std::vector<std::string> out;
  for (const auto& c : commands_) out.push_back(c->name);
  return out;
}

int CommandTable::run(int argc, char** argv) {
  g_tool = tool_;
  try {
    try {
      app_.parse(argc, argv);
    } catch (const CLI::Success& e) {
      return app_.exit(e);  // --help: prints usage, status 0
    } catch (const CLI::ParseError& e) {
      std::cerr << tool_ << ": error: " << e.what() << "\n"
                << "Run '" << tool_ << " --help' or '" << tool_ << " <command> --help' for usage.\n";
      return static_cast<int>(ErrorCode::BadUsage);
    }
    Command* chosen = nullptr;
    for (auto& c : commands_)
      if (c->app->parsed()) chosen = c.get();
    if (!chosen) {  // require_subcommand(1) makes this unreachable; keep the contract anyway
      std::cerr << tool_ << ": error: no command given\n";
      return static_cast<int>(ErrorCode::BadUsage);
    }

    // The thread budget is process-wide inside TBB; it lives exactly as long as the command.
    std::optional<tbb::global_control> threads;
    if (chosen->common.threads > 0)
      threads.emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(chosen->common.threads));

    g_cancel.store(false);
    auto previous = std::signal(SIGINT, on_sigint);
    // Past a file-size limit (ulimit -f) a write then fails with EFBIG, which
    // the safe writer reports, instead of the signal killing the process.
    std::signal(SIGXFSZ, SIG_IGN);
    // Every file the command writes is staged and renamed into place only
    // when the whole command succeeded (io/atomic_file_write.hpp).
    io::CommitGroup outputs;
    RunContext ctx;
    if (!chosen->common.max_memory.empty()) ctx.max_memory_bytes = parse_memory_size(chosen->common.max_memory);
    ctx.threads = chosen->common.threads;
    ctx.cancel = &g_cancel;
    g_command_clock.restart();
    g_written.clear();
    int status = chosen->body(chosen->common, ctx);
    std::signal(SIGINT, previous);
    if (ctx.cancelled()) {
      std::cerr << tool_ << ": error: cancelled\n";
      return static_cast<int>(ErrorCode::Cancelled);
    }
    if (status == 0) {
      outputs.commit();
      for (const std::string& path : g_written) log("wrote " + path);
    }
    return status;
  } catch (const Error& e) {
    std::cerr << tool_ << ": error: " << e.what() << "\n";
    return e.exit_status();
  } catch (const std::bad_alloc&) {
    // Treated like a refused allocation (ErrorCode::ResourceLimit): the input is too large.
    std::cerr << tool_ << ": error: out of memory (input too large for this machine)\n";
    return static_cast<int>(ErrorCode::BadInput);
  } catch (const std::exception& e) {
    std::cerr << tool_ << ": internal error: " << e.what() << "\n";
    return static_cast<int>(ErrorCode::Internal);
  } catch (...) {
    std::cerr << tool_ << ": internal error: unknown exception\n";
    return static_cast<int>(ErrorCode::Internal);
  }
}

Input load_input(const CommonOptions& opt, const RunContext& ctx, PolygonFaces faces) {
  Input in;
  Stopwatch sw;
  in.mesh = read_mesh(opt.mesh_path, {}, &in.attributes);
  in.load_s = sw.seconds();
  g_load_s = in.load_s;
  for (const std::string& note : in.attributes.notes) log(note);
  if (faces == PolygonFaces::Triangulate && !in.mesh.is_triangle_mesh()) {
    ctx.check_cancel();
    sw.restart();
    TriangulatedMesh t = triangulate_polygons(in.mesh, opt.mesh_path);
    in.polygons = std::move(in.mesh);
    in.mesh = std::move(t.mesh);
    in.face_of = std::move(t.face_of);
    in.triangulate_s = sw.seconds();
    log("triangulated the " + std::to_string(in.polygons.num_faces()) + " faces of " + opt.mesh_path + " into " +
        std::to_string(in.mesh.num_faces()) + " triangles (ear clipping); outputs on its vertices keep its faces");
  }
  if (opt.subdivide > 0) {
    ctx.check_cancel();
    if (!in.mesh.is_triangle_mesh()) {
      int32_t f = 0;
      while (f < in.mesh.num_faces() && in.mesh.face(f).size() == 3) ++f;
      fail(ErrorCode::BadInput, "--subdivide needs a triangle mesh, but face " + std::to_string(f) + " of " +
                                    opt.mesh_path + " has " + std::to_string(in.mesh.face(f).size()) + " vertices");
    }
    // Refused before allocating: face indices beyond int32 (exit 3) or more
    // memory than --max-memory for the mesh and its derived data.
    try {
      check_subdivision(in.mesh, opt.subdivide, ctx);
    } catch (const Error& e) {
      fail(e.code(), "--subdivide " + std::to_string(opt.subdivide) + ": " + e.what());
    }
    if (!in.attributes.vertex.empty()) {
      log("--subdivide: the input's " + std::to_string(in.attributes.vertex.size()) +
          " vertex attribute(s) are not carried to the outputs (subdivision makes new vertices)");
      in.attributes.vertex.clear();
    }
    if (in.triangulated()) {  // new vertices: the file's faces no longer describe the mesh
      in.polygons = Mesh{};
      in.face_of.clear();
    }
    sw.restart();
    in.mesh = subdivide_midpoint(in.mesh, opt.subdivide);
    in.subdivide_s = sw.seconds();
    g_subdivide_s = in.subdivide_s;
  }
  return in;
}

Json input_json(const CommonOptions& opt, const Input& in) {
  Json j{{"file", opt.mesh_path},
         {"subdivide", opt.subdivide},
         {"n_vertices", in.mesh.num_vertices()},
         {"n_faces", in.mesh.num_faces()}};
  if (in.triangulated())
    j["triangulated"] = {{"polygons", in.polygons.num_faces()}, {"triangles", in.mesh.num_faces()},
                         {"seconds", in.triangulate_s}};
  return j;
}

SurfacePoint point_on_file_face(const Input& in, const SurfacePoint& p, const std::string& what) {
  if (!in.triangulated() || p.face < 0) return p;
  const Mesh& poly = in.polygons;
  if (p.face >= poly.num_faces())
    fail(ErrorCode::BadInput, what + ": face " + std::to_string(p.face) + " does not exist (" +
                                  std::to_string(poly.num_faces()) + " faces)");
  const auto fv = poly.face(p.face);
  double x[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    x[0] += p.bary[k] * poly.x[fv[k]];
    x[1] += p.bary[k] * poly.y[fv[k]];
    x[2] += p.bary[k] * poly.z[fv[k]];
  }
  // The polygon's triangles are consecutive in face order; barycentrics of x
  // in each by least squares (x may sit off a warped polygon's triangles).
  const auto first = std::lower_bound(in.face_of.begin(), in.face_of.end(), p.face);
  for (auto it = first; it != in.face_of.end() && *it == p.face; ++it) {
    const int32_t t = static_cast<int32_t>(it - in.face_of.begin());
    const auto tv = in.mesh.face(t);
    const double a[3] = {in.mesh.x[tv[0]], in.mesh.y[tv[0]], in.mesh.z[tv[0]]};
    const double e1[3] = {in.mesh.x[tv[1]] - a[0], in.mesh.y[tv[1]] - a[1], in.mesh.z[tv[1]] - a[2]};
    const double e2[3] = {in.mesh.x[tv[2]] - a[0], in.mesh.y[tv[2]] - a[1], in.mesh.z[tv[2]] - a[2]};
    const double d[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
    const double g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2], g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2],
                 g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    const double r1 = e1[0] * d[0] + e1[1] * d[1] + e1[2] * d[2], r2 = e2[0] * d[0] + e2[1] * d[1] + e2[2] * d[2];
    const double det = g11 * g22 - g12 * g12;
    if (!(det > 0)) continue;
    const double b1 = (g22 * r1 - g12 * r2) / det, b2 = (g11 * r2 - g12 * r1) / det, b0 = 1 - b1 - b2;
    if (b0 >= -1e-9 && b1 >= -1e-9 && b2 >= -1e-9) {
      SurfacePoint q;
      q.face = t;
      q.bary = {std::max(b0, 0.0), std::max(b1, 0.0), std::max(b2, 0.0)};
      const double s = q.bary[0] + q.bary[1] + q.bary[2];
      for (double& b : q.bary) b /= s;
      return q;
    }
  }
  fail(ErrorCode::BadInput, what + ": the point with weights of corners 0, 1, 2 of face " + std::to_string(p.face) +
                                " lies outside that polygon");
}

const Mesh& output_faces(const Input& in) { return in.triangulated() ? in.polygons : in.mesh; }

Mesh with_positions(const Input& in, const Mesh& moved) {
  if (!in.triangulated()) return moved;
  Mesh out = in.polygons;
  out.x = moved.x;
  out.y = moved.y;
  out.z = moved.z;
  return out;
}

int threads_used([[maybe_unused]] const CommonOptions& opt) {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

void check_uv_output(const CommonOptions& opt, const std::string& command) {
  if (!opt.output.empty() && io::lower_extension(opt.output) == "off")
    fail(ErrorCode::BadUsage, command + ": -o " + opt.output +
                                  ": OFF has no texture coordinates for the result's UVs; use .obj or .ply");
}

void refuse_output(const CommonOptions& opt, const std::string& command, const std::string& result) {
  if (!opt.output.empty())
    fail(ErrorCode::BadUsage, command + ": -o " + opt.output + ": this command writes no file; " + result);
}

WriteOptions carried_attributes(const Input& in, bool positions_changed, bool result_uv) {
  WriteOptions wo;
  wo.float_positions = in.attributes.float_positions;
  for (const VertexProperty& p : in.attributes.vertex) {
    if (static_cast<int32_t>(p.values.size()) != in.mesh.num_vertices()) continue;
    if (positions_changed && (p.name == "nx" || p.name == "ny" || p.name == "nz")) continue;
    if (result_uv && (p.name == "u" || p.name == "v")) continue;
    wo.vertex_properties.push_back(p);
  }
  return wo;
}

void add_result(WriteOptions& wo, VertexProperty p) {
  auto& props = wo.vertex_properties;
  props.erase(std::remove_if(props.begin(), props.end(), [&](const VertexProperty& q) { return q.name == p.name; }),
              props.end());
  if (wo.off_colour.empty()) wo.off_colour = p.name;  // OFF shows the first result, not an input attribute
  props.push_back(std::move(p));
}

void write_output_mesh(const CommonOptions& opt, const Mesh& m, const WriteOptions& wo) {
  if (opt.output.empty()) return;
  write_mesh(opt.output, m, wo);
  log_written(opt.output);
}

void log_written(const std::string& path) { g_written.push_back(path); }

void emit(const CommonOptions& opt, const Json& result, const std::function<void(std::ostream&)>& human) {
  if (opt.json) {
    // Keys every command's JSON has (issue 22 item 8): the version that made
    // it, the threads it ran with, the -o file and the preview image(s) (null
    // when none), and the timings below.
    Json j = result;
    if (!j.contains("output")) j["output"] = opt.output.empty() ? Json(nullptr) : Json(opt.output);
    // timings: load_s, subdivide_s and total_s (command start to this report) in every command.
    Json& t = j["timings"];
    if (!t.is_object()) t = Json::object();
    if (!t.contains("load_s")) t["load_s"] = g_load_s;
    if (!t.contains("subdivide_s")) t["subdivide_s"] = g_subdivide_s;
    if (!t.contains("total_s")) t["total_s"] = g_command_clock.seconds();
    if (!j.contains("preview"))
      j["preview"] = g_previews.empty()       ? Json(nullptr)
                     : g_previews.size() == 1 ? Json(g_previews[0])
                                              : Json(g_previews);
    if (!j.contains("threads")) j["threads"] = threads_used(opt);
    j["version"] = locus_version(nullptr, nullptr, nullptr);
    std::cout << j.dump(2) << std::endl;
  } else {
    human(std::cout);
    std::cout.flush();
  }
}

void log(const std::string& text) { std::cerr << g_tool << ": " << text << "\n"; }

TimeSpec parse_time_spec(const std::string& text) {
  auto bad = [&]() -> TimeSpec {
    fail(ErrorCode::BadUsage, "--t '" + text + "': expected a positive time (0.001, 1e-3) or a multiple of h^2 (h2, 2h2, 500h2)");
  };
  TimeSpec spec;
  std::string number = text;
  spec.times_h2 = false;
  if (number.size() >= 2 && number.compare(number.size() - 2, 2, "h2") == 0) {
    spec.times_h2 = true;
    number.resize(number.size() - 2);
  }
  if (number.empty()) {
    if (!spec.times_h2) return bad();
    spec.value = 1.0;  // "h2" alone
    return spec;
  }
  double v = 0;
  const char* first = number.data();
  const char* last = first + number.size();
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last || !std::isfinite(v) || !(v > 0)) return bad();
  spec.value = v;
  return spec;
}

void add_heat_time_options(CLI::App* app, HeatTimeOptions& ht, const std::string& default_text, bool factor_alias) {
  app->add_option("--t", ht.t_text,
                  "Diffusion time: absolute (1e-3) or a multiple of h^2, h = mean edge length (h2, 4h2); default " +
                      default_text)
      ->check(non_empty());
  if (factor_alias)
    app->add_option("--t-factor", ht.t_factor, "Deprecated spelling of --t: --t-factor C is --t Ch2")
        ->check(non_empty());
}

std::string heat_time_text(const HeatTimeOptions& ht, double t_factor) {
  return ht.t_text.empty() ? format_number(t_factor) + "h2" : ht.t_text;
}

double parse_h2_multiple(const std::string& text, const std::string& option, bool allow_zero) {
  double c = -1;
  const char* first = text.data();
  const char* last = first + text.size();
  auto [ptr, ec] = std::from_chars(first, last, c);
  if (ec != std::errc() || ptr != last || !(allow_zero ? c >= 0 : c > 0) || !std::isfinite(c))
    fail(ErrorCode::BadUsage, option + " must be a finite " + (allow_zero ? "number >= 0" : "positive number") +
                                  " (got '" + text + "')");
  return c;
}

TimeSpec heat_time_spec(const HeatTimeOptions& ht, const TimeSpec& default_spec) {
  if (!ht.t_factor.empty()) {
    if (!ht.t_text.empty())
      fail(ErrorCode::BadUsage, "--t and --t-factor name one diffusion time; give --t only (--t-factor C is --t Ch2)");
    const double c = parse_h2_multiple(ht.t_factor, "--t-factor", false);
    log("--t-factor is deprecated and will be removed; use --t " + ht.t_factor + "h2");
    return TimeSpec{c, true};
  }
  return ht.t_text.empty() ? default_spec : parse_time_spec(ht.t_text);
}

double heat_t_factor(const TimeSpec& ts, double h) {
  if (ts.times_h2) return ts.value;
  if (!(h > 0) || !std::isfinite(h))
    fail(ErrorCode::BadInput, "mean edge length is " + format_number(h) + ": cannot express --t as a multiple of h^2");
  return ts.value / (h * h);
}

void add_operator_options(CLI::App* app, OperatorSpec& spec) {
  app->add_option("--operator", spec.kind, "Operator: heat (M - tL, default) or laplacian (-L + eps M)")
      ->check(CLI::IsMember({"heat", "laplacian"}));
  app->add_option("--t", spec.t_text, "Diffusion time of the heat operator: absolute (1e-3) or a multiple of h^2 (2h2); default h2")->check(non_empty());
}

void validate_operator_spec(const OperatorSpec& spec) {
  if (spec.kind == "laplacian" && !spec.t_text.empty())
    fail(ErrorCode::BadUsage, "--t applies to --operator heat only");
  if (!spec.t_text.empty()) parse_time_spec(spec.t_text);
}

BuiltOperator build_operator(const Mesh& m, const OperatorSpec& spec) {
  validate_operator_spec(spec);
  const std::string where = m.source.empty() ? std::string("the mesh") : m.source;
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, where + " has no faces");
  // One edge incidence for the checks, h and the assembly (each would build its own).
  const EdgeIncidence inc = edge_incidence(m);
  check_requirements(m, MeshRequirements{}, analyze_mesh(m, inc));
  BuiltOperator op;
  op.h = mean_edge_length(m, inc.edges);
  if (!(op.h > 0) || !std::isfinite(op.h))
    fail(ErrorCode::BadInput, where + ": mean edge length is " + format_number(op.h) + ", cannot scale the operator");
  if (spec.kind == "laplacian") {
    op.A = regularized_laplacian(m, kLaplacianRegularization, &inc);
  } else {
    op.t = spec.t_text.empty() ? op.h * op.h : parse_time_spec(spec.t_text).resolve(op.h);
    op.A = heat_operator(m, op.t, &inc);
  }
  return op;
}

std::size_t parse_memory_size(const std::string& text) {
  auto bad = [&]() -> std::size_t {
    fail(ErrorCode::BadUsage, "--max-memory '" + text + "': expected a positive size in bytes or with a K, M, G or T suffix (4G, 512M)");
  };
  std::string number = text, unit;
  while (!number.empty() && std::isalpha(static_cast<unsigned char>(number.back()))) {
    unit.insert(unit.begin(), static_cast<char>(std::toupper(static_cast<unsigned char>(number.back()))));
    number.pop_back();
  }
  double scale = 1;
  if (unit.empty() || unit == "B") {
    scale = 1;
  } else {
    static const char* const kUnits = "KMGT";
    const char* at = unit.size() <= 3 ? std::strchr(kUnits, unit[0]) : nullptr;
    const std::string rest = unit.substr(1);
    if (!at || !(rest.empty() || rest == "B" || rest == "IB")) return bad();
    scale = std::pow(1024.0, static_cast<double>(at - kUnits + 1));
  }
  double v = 0;
  const char* first = number.data();
  const char* last = first + number.size();
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (number.empty() || ec != std::errc() || ptr != last || !std::isfinite(v) || !(v > 0)) return bad();
  const double bytes = std::floor(v * scale);
  if (!(bytes >= 1) || bytes >= 0x1p63) return bad();
  return static_cast<std::size_t>(bytes);
}

void add_factor_cache_options(CLI::App* app, FactorCacheOptions& fc) {
  app->add_option("--save", fc.save, "Save the factor(s) to FILE (.locus) after factoring")
      ->check(output_file({"locus"}));
  app->add_option("--load", fc.load,
                  "Load the factor(s) from FILE instead of factoring; refused (exit 3) if made for another mesh, "
                  "operator or t");
}

void validate_factor_cache_options(const FactorCacheOptions& fc) {
  if (!fc.save.empty() && !fc.load.empty())
    fail(ErrorCode::BadUsage, "--save and --load exclude each other (load " + fc.load + " or save " + fc.save + ")");
}

namespace {

std::string operator_label(const std::string& kind, double t) {
  return t != 0 ? kind + " (t = " + format_number(t) + ")" : kind;
}

std::string operator_list(const std::vector<std::string>& kinds, const std::vector<double>& t) {
  std::string s;
  for (size_t k = 0; k < kinds.size(); ++k) s += (k ? ", " : "") + operator_label(kinds[k], t[k]);
  return s;
}

}  // namespace

Factors factor_or_load(const FactorCacheOptions& fc, const Mesh& m, std::span<const FactorRequest> ops,
                       const RunContext& ctx) {
  validate_factor_cache_options(fc);
  if (ops.empty() || !ops[0].A) fail(ErrorCode::Internal, "factor_or_load: no operator");
  const CscMatrix& A0 = *ops[0].A;
  Factors F;
  Stopwatch sw;
  if (!fc.load.empty()) {
    // The loaded factor lives in memory whole: its file size is what it costs.
    std::error_code size_ec;
    const uintmax_t bytes = std::filesystem::file_size(fc.load, size_ec);
    if (!size_ec && bytes > memory_limit_bytes(ctx))
      fail(ErrorCode::ResourceLimit, fc.load + ": loading it needs " + format_number(bytes / 1073741824.0) +
                                         " GiB, more than the memory limit of " +
                                         format_number(memory_limit_bytes(ctx) / 1073741824.0) +
                                         " GiB (raise it with --max-memory)");
    const uint64_t hash = mesh_content_hash(m);
    LoadedFactors L = load_factors(fc.load, hash);
    std::vector<std::string> want_kinds;
    std::vector<double> want_t;
    for (const FactorRequest& r : ops) {
      want_kinds.push_back(r.kind);
      want_t.push_back(r.t);
    }
    bool same = L.factors.size() == ops.size();
    for (size_t k = 0; same && k < ops.size(); ++k)
      same = L.operator_kinds[k] == ops[k].kind &&
             std::abs(L.t[k] - ops[k].t) <= 1e-12 * std::max(std::abs(L.t[k]), std::abs(ops[k].t));
    if (!same)
      fail(ErrorCode::BadInput, fc.load + ": holds factors of " + operator_list(L.operator_kinds, L.t) +
                                    ", but this command needs " + operator_list(want_kinds, want_t) +
                                    " (save it again with --save and these options)");
    const SymbolicFactor& S = *L.factors[0].symbolic;
    if (S.n != A0.ncols || S.a_nnz != A0.nnz() || S.a_pattern_hash != pattern_hash(A0))
      fail(ErrorCode::BadInput, fc.load + ": the saved factor is of another matrix pattern (" + std::to_string(S.n) +
                                    " columns, " + std::to_string(S.a_nnz) + " entries) than this operator (" +
                                    std::to_string(A0.ncols) + " columns, " + std::to_string(A0.nnz()) + " entries)");
    F.symbolic = L.factors[0].symbolic;
    F.factors = std::move(L.factors);
    F.loaded = true;
    F.load_s = sw.seconds();
    log("loaded " + std::to_string(F.factors.size()) + " factor(s) from " + fc.load + " in " +
        format_number(F.load_s) + " s");
    return F;
  }
  for (const FactorRequest& r : ops)
    if (!r.A || r.A->ncols != A0.ncols || r.A->nnz() != A0.nnz())
      fail(ErrorCode::Internal, "factor_or_load: the operators do not share one pattern");
  const Ordering ord = order_matrix(A0, {}, ctx);
  F.order_s = sw.seconds();
  ctx.check_cancel();
  sw.restart();
  F.symbolic = analyze(A0, ord);
  F.analyze_s = sw.seconds();
  for (const FactorRequest& r : ops) {
    ctx.check_cancel();
    sw.restart();
    F.factors.push_back(factorize(F.symbolic, *r.A, ctx));
    F.numeric_s += sw.seconds();
  }
  if (!fc.save.empty()) {
    ctx.check_cancel();
    sw.restart();
    std::vector<FactorEntry> entries;
    for (size_t k = 0; k < ops.size(); ++k) entries.push_back({ops[k].kind, ops[k].t, &F.factors[k]});
    save_factors(fc.save, mesh_content_hash(m), entries);
    F.save_s = sw.seconds();
    log("saved " + std::to_string(entries.size()) + " factor(s) to " + fc.save);
  }
  return F;
}

Json factor_cache_json(const FactorCacheOptions& fc, const Factors& f) {
  Json j;
  j["loaded"] = fc.load.empty() ? Json(nullptr) : Json(fc.load);
  j["saved"] = fc.save.empty() ? Json(nullptr) : Json(fc.save);
  j["load_s"] = f.load_s;
  j["save_s"] = f.save_s;
  return j;
}

CLI::Validator output_file(std::vector<std::string> extensions) {
  return CLI::Validator(
      [extensions](std::string& path) -> std::string {
        if (path.empty()) return "must not be empty";
        const std::string ext = io::lower_extension(path);
        if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) {
          std::string list;
          for (const std::string& e : extensions) list += (list.empty() ? "." : ", .") + e;
          return path + ": unsupported extension '" + ext + "' (expected " + list + ")";
        }
        try {
          io::check_output_path(path);
        } catch (const Error& e) {
          return e.what();
        }
        return std::string();
      },
      "OUTPUT-FILE");
}

void add_preview_option(CLI::App* app, PreviewOptions& preview) {
  app->add_option("--preview", preview.path,
                  "Render a PNG of the mesh coloured by the result, with a legend and markers (800x800)")
      ->check(output_file({"png"}));
  app->add_option("--view", preview.view,
                  "Preview camera side as x,y,z (the camera looks from that side towards the mesh); default: from "
                  "the mesh's principal axes, upright for y-up and z-up files");
}

void check_preview_path(const std::string& path) {
  if (path.empty()) return;
  if (io::lower_extension(path) != "png") fail(ErrorCode::BadUsage, "--preview " + path + ": the preview is a PNG image; name it *.png");
  io::check_output_path(path);
}

namespace {

std::optional<std::array<double, 3>> parse_view(const std::string& text) {
  if (text.empty()) return std::nullopt;
  std::array<double, 3> d{};
  size_t at = 0;
  int k = 0;
  bool ok = true;
  for (; k < 3 && ok; ++k) {
    const size_t end = k < 2 ? text.find(',', at) : text.size();
    if (end == std::string::npos) {
      ok = false;
      break;
    }
    const std::string part = text.substr(at, end - at);
    const char* first = part.data();
    auto [ptr, ec] = std::from_chars(first, first + part.size(), d[k]);
    ok = !part.empty() && ec == std::errc() && ptr == first + part.size() && std::isfinite(d[k]);
    at = end + 1;
  }
  if (!ok || k != 3 || !(d[0] != 0 || d[1] != 0 || d[2] != 0))
    fail(ErrorCode::BadUsage, "--view '" + text + "': expected three numbers x,y,z, not all zero (e.g. 0,0,1: look from +z)");
  return d;
}

}  // namespace

void check_preview_options(const PreviewOptions& preview) {
  check_preview_path(preview.path);
  parse_view(preview.view);
  if (!preview.view.empty() && preview.path.empty()) fail(ErrorCode::BadUsage, "--view sets the camera of --preview; give --preview FILE.png too");
}

std::string preview_path_with(const std::string& path, const std::string& suffix) {
  const size_t dot = path.rfind('.');
  const size_t slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + suffix;
  return path.substr(0, dot) + suffix + path.substr(dot);
}

void write_preview(const Mesh& m, std::span<const double> values, PreviewKind kind, const PreviewOptions& preview,
                   const PreviewContent& content, const std::string& path_override) {
  const std::string path = path_override.empty() ? preview.path : path_override;
  if (path.empty()) return;
  check_preview_path(path);
  RasterOptions ro;
  ro.coloring = kind == PreviewKind::Scalar   ? Coloring::Scalar
                : kind == PreviewKind::Labels ? Coloring::Labels
                                              : Coloring::Checker;
  ro.view = parse_view(preview.view);
  ro.title = content.title;
  ro.markers = content.markers;
  ro.marker_label = content.marker_label;
  ro.edges = content.edges;
  ro.clip = content.clip;
  const RasterImage img = rasterize_mesh(m, values, ro);
  write_png(path, img.width, img.height, img.rgb);
  g_previews.push_back(path);
  log_written(path);
}

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

double median(std::vector<double> v) {
  if (v.empty()) fail(ErrorCode::Internal, "median of an empty sample");
  std::sort(v.begin(), v.end());
  const size_t k = v.size() / 2;
  return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
}

std::vector<double> random_vector(size_t n, uint64_t seed) {
  std::vector<double> v(n);
  uint64_t s = seed;
  for (size_t i = 0; i < n; ++i) {
    // splitmix64 (Steele, Lea, Flood 2014): a full-period, well-mixed 64-bit stream.
    uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    v[i] = static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;  // 53 random bits -> [-1, 1)
  }
  return v;
}

double relative_residual(const CscMatrix& A, const double* x, const double* b) {
  std::vector<double> ax(static_cast<size_t>(A.nrows));
  symmetric_multiply(A, x, ax.data());
  double rr = 0, bb = 0;
  for (int32_t i = 0; i < A.nrows; ++i) {
    const double d = ax[i] - b[i];
    rr += d * d;
    bb += b[i] * b[i];
  }
  return bb > 0 ? std::sqrt(rr / bb) : std::sqrt(rr);
}

}  // namespace locus::cli
