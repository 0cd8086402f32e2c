// The command table of the locus tools (cli_command_table.hpp): parsing, exit
// statuses, the SIGINT cancel flag, the thread budget and the RunContext.
#include "tools/cli/cli_command_table.hpp"

#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstring>
#include <iostream>
#include <new>
#include <optional>

#include "locus/error.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/io/file_extension.hpp"
#include "locus/locus.h"
#include "tools/cli/cli_report.hpp"
#include "tools/cli/written_files.hpp"

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

// Files the command staged (log_written), logged once they are committed.
std::vector<std::string> g_written;

}  // namespace

void log_written(const std::string& path) { g_written.push_back(path); }

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
  app->add_option("mesh-file", c.mesh_path,
                  "Input mesh (.off .obj .ply; glTF .gltf .glb, FBX, Collada .dae, STL, 3MF and the other formats "
                  "assimp reads)")->required();
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
  app->add_option("--operator", c.mesh_operator,
                  "Laplacian: auto (default: cotan on a clean manifold mesh, robust when it has defects), cotan, or "
                  "robust (intrinsic Delaunay of the tufted cover: non-manifold and degenerate meshes)")
      ->check(CLI::IsMember({"auto", "cotan", "robust"}));
  app->add_flag("--no-weld", c.no_weld,
                "Asset files (glTF, FBX, ...): keep the file's vertices instead of welding them by position");
  cmd->app = app;
  commands_.push_back(std::move(cmd));
  return app;
}

void drop_mesh_operator_option(CLI::App* app) {
  if (CLI::Option* o = app->get_option_no_throw("--operator")) app->remove_option(o);
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
  report_begin(tool_);
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
    ctx.message = [](std::string_view text) { log(std::string(text)); };  // the engine's notes: log lines
    report_begin(tool_);
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

int threads_used([[maybe_unused]] const CommonOptions& opt) {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
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

}  // namespace locus::cli
