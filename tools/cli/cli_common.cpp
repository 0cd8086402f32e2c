// The shared grammar and helpers of the locus tools (see cli_common.hpp):
// parsing, exit statuses, the SIGINT cancel flag, the thread budget, loading
// and subdividing the input, JSON output, --t / --operator parsing.
#include "tools/cli/cli_common.hpp"

#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <limits>
#include <new>
#include <optional>

#include "kernels/mesh_generators.hpp"
#include "kernels/mesh_operators.hpp"
#include "kernels/mesh_topology.hpp"
#include "locus/error.hpp"
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

}  // namespace

struct CommandTable::Command {
  std::string name;
  CLI::App* app = nullptr;
  CommonOptions common;
  CommandBody body;
};

CommandTable::CommandTable(std::string tool_name, std::string description)
    : tool_(std::move(tool_name)), app_(std::move(description), tool_) {
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
  app->add_option("-o,--output", c.output, "Result file; the format follows the extension (.ply .obj .off)");
  app->add_option("--threads", c.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
  app->add_option("--seed", c.seed, "Seed of every random choice (default 1)");
  app->add_option("--subdivide", c.subdivide, "1:4 midpoint subdivision K times after loading")
      ->check(CLI::Range(0, 16));
  cmd->app = app;
  commands_.push_back(std::move(cmd));
  return app;
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
    RunContext ctx;
    ctx.threads = chosen->common.threads;
    ctx.cancel = &g_cancel;
    int status = chosen->body(chosen->common, ctx);
    std::signal(SIGINT, previous);
    if (ctx.cancelled()) {
      std::cerr << tool_ << ": error: cancelled\n";
      return static_cast<int>(ErrorCode::Cancelled);
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

Input load_input(const CommonOptions& opt, const RunContext& ctx) {
  Input in;
  Stopwatch sw;
  in.mesh = read_mesh(opt.mesh_path);
  in.load_s = sw.seconds();
  if (opt.subdivide > 0) {
    ctx.check_cancel();
    if (!in.mesh.is_triangle_mesh()) {
      int32_t f = 0;
      while (f < in.mesh.num_faces() && in.mesh.face(f).size() == 3) ++f;
      fail(ErrorCode::BadInput, "--subdivide needs a triangle mesh, but face " + std::to_string(f) + " of " +
                                    opt.mesh_path + " has " + std::to_string(in.mesh.face(f).size()) + " vertices");
    }
    // Faces are indexed by int32 offsets (3 per triangle): refuse before allocating.
    const double faces_after = in.mesh.num_faces() * std::pow(4.0, opt.subdivide);
    if (3.0 * faces_after > static_cast<double>(std::numeric_limits<int32_t>::max()))
      fail(ErrorCode::BadUsage, "--subdivide " + std::to_string(opt.subdivide) + " would make " +
                                    std::to_string(static_cast<long long>(faces_after)) + " faces from " +
                                    opt.mesh_path + " (limit 715827882)");
    sw.restart();
    in.mesh = subdivide_midpoint(in.mesh, opt.subdivide);
    in.subdivide_s = sw.seconds();
  }
  return in;
}

Json input_json(const CommonOptions& opt, const Input& in) {
  return {{"file", opt.mesh_path},
          {"subdivide", opt.subdivide},
          {"n_vertices", in.mesh.num_vertices()},
          {"n_faces", in.mesh.num_faces()}};
}

void write_output_mesh(const CommonOptions& opt, const Mesh& m) {
  if (opt.output.empty()) return;
  write_mesh(opt.output, m);
  log("wrote " + opt.output);
}

void emit(const CommonOptions& opt, const Json& result, const std::function<void(std::ostream&)>& human) {
  if (opt.json) {
    std::cout << result.dump(2) << std::endl;
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

void add_operator_options(CLI::App* app, OperatorSpec& spec) {
  app->add_option("--operator", spec.kind, "Operator: heat (M - tL, default) or laplacian (-L + eps M)")
      ->check(CLI::IsMember({"heat", "laplacian"}));
  app->add_option("--t", spec.t_text, "Diffusion time of the heat operator: absolute (1e-3) or a multiple of h^2 (2h2); default h2");
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
  check_requirements(m, MeshRequirements{});
  BuiltOperator op;
  op.h = mean_edge_length(m);
  if (!(op.h > 0) || !std::isfinite(op.h))
    fail(ErrorCode::BadInput, where + ": mean edge length is " + format_number(op.h) + ", cannot scale the operator");
  if (spec.kind == "laplacian") {
    op.A = regularized_laplacian(m);
  } else {
    op.t = spec.t_text.empty() ? op.h * op.h : parse_time_spec(spec.t_text).resolve(op.h);
    op.A = heat_operator(m, op.t);
  }
  return op;
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
