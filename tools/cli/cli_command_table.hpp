// The shared grammar of the `locus` and `locus-bench` tools (DESIGN.md "The
// command-line contract"): `tool <command> <mesh-file> [options]` with the
// common options --json, -o/--output, --threads, --seed, --subdivide,
// --max-memory; exit status 0 ok, 2 bad usage, 3 bad input, 4 numerical
// failure, 5 cancelled.
//
// A command is a name, a description, its own options and a body. The
// CommandTable owns parsing, the thread budget (tbb::global_control), the
// SIGINT cancel flag, the RunContext (its notes go to stderr as log lines)
// and the mapping from exceptions to exit statuses, so a new command only
// declares its options and writes its body: load the input with
// load_input() (cli_input.hpp), compute, emit() a JSON object (cli_report.hpp).
#pragma once
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "locus/run_context.hpp"

namespace locus::cli {

// Options every command accepts, with the contract's defaults.
struct CommonOptions {
  std::string mesh_path;  // positional <mesh-file>
  bool json = false;      // one JSON object on stdout, logs on stderr
  std::string output;     // -o FILE: result file, format from the extension ("" = none)
  int threads = 0;        // 0 = all cores
  uint64_t seed = 1;      // every random choice derives from it
  int subdivide = 0;      // 1:4 midpoint subdivisions after loading
  std::string max_memory; // --max-memory SIZE as given ("" = default: 80% of physical memory)
  std::string mesh_operator = "auto";  // --operator auto|cotan|robust (operator_choice.hpp)
  bool no_weld = false;   // --no-weld: keep an asset file's vertices (no welding by position)
};

// Commands whose own --operator names the matrix they factor (factor: heat or
// laplacian) take the mesh-level --operator off first.
void drop_mesh_operator_option(CLI::App* app);

// A command's body runs after a successful parse and returns the exit status
// (normally 0); failures are thrown as locus::Error and mapped by the table.
using CommandBody = std::function<int(const CommonOptions&, const RunContext&)>;

class CommandTable {
 public:
  // `tool_name` prefixes every message ("locus: error: ...").
  CommandTable(std::string tool_name, std::string description);
  ~CommandTable();
  CommandTable(const CommandTable&) = delete;
  CommandTable& operator=(const CommandTable&) = delete;

  // Declares `<tool> <name> <mesh-file> [common options]`; the caller adds the
  // command's own options to the returned app (owned by the table).
  CLI::App* add(const std::string& name, const std::string& description, CommandBody body);

  // Lists a command with its own grammar in --help without parsing it (the caller dispatches it).
  void add_listing(const std::string& name, const std::string& description);

  // Names of the commands added with add(), in order.
  std::vector<std::string> names() const;

  // Parses argv, runs the chosen command and returns the exit status. Never throws.
  int run(int argc, char** argv);

 private:
  struct Command;
  std::string tool_;
  CLI::App app_;
  std::vector<std::unique_ptr<Command>> commands_;
};

// Monotonic stopwatch for phase timings, in seconds.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

// --max-memory SIZE: bytes, or a number with a K, M, G or T suffix (powers of
// 1024; "512M", "1.5G", "2GiB" and "2GB" are the same as their binary forms).
// Throws Error(BadUsage) naming the text otherwise. The CommandTable parses it
// before the body runs and puts it in RunContext::max_memory_bytes.
std::size_t parse_memory_size(const std::string& text);

// The worker threads a command runs with: --threads N, or all cores for 0
// (what the JSON key `threads` reports).
int threads_used(const CommonOptions& opt);

// Rejects an empty option value: `--t ''` would otherwise read as "not given"
// and silently fall back to the default.
inline CLI::Validator non_empty() {
  return CLI::Validator([](std::string& v) { return v.empty() ? std::string("must not be empty") : std::string(); },
                        "NONEMPTY");
}

// A CLI11 check for options naming a file the command writes: the extension
// is one of `extensions` (lower case, no dot) and io::check_output_path()
// accepts the path (folder exists and is writable; the target is absent or a
// regular file). It runs at parse time, so a bad output path is exit 2 before
// any input is read.
CLI::Validator output_file(std::vector<std::string> extensions);

}  // namespace locus::cli
