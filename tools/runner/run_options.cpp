// The command line of `locus run`: inputs are the arguments between PIPELINE
// and the first option; every later argument that is not one of the runner's
// own options goes to the pipeline unchanged (--sites 200 --iters 20 ...).
#include "tools/runner/run_options.hpp"

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <iostream>

#include "locus/error.hpp"

namespace locus::runner {
namespace {

const char* kUsage =
    "Usage: locus run PIPELINE FILE-OR-FOLDER... [pipeline options] --out DIR [--jobs J] [--threads N]\n"
    "                 [--ext EXT|none] [--preview] [--recursive] [--resume] [--shard K/N] [--json]\n"
    "       locus run --merge DIR... [--out DIR] [--json]\n"
    "Runs `locus PIPELINE` on every input (folders: the mesh files inside, .off/.obj/.ply and the asset\n"
    "formats .glb/.gltf/.fbx/.dae/.stl/..., sorted; with --recursive their subfolders too), J at a time\n"
    "with N/J threads each. Writes DIR/<name>.<EXT> (the pipeline's -o\n"
    "output), DIR/<name>.json (one report per input), with --preview DIR/<name>.png (one image per input),\n"
    "and DIR/summary.json (also on stdout with --json). A\n"
    "failing input is reported and skipped. --resume skips inputs whose report in DIR says ok for the same\n"
    "pipeline and options. --shard K/N runs the K-th of N deterministic parts of the sorted inputs and writes\n"
    "DIR/summary-K-of-N.json; --merge combines the summaries found in the given folders into one\n"
    "(DIR/summary.json of --out, default the first folder), as if one run had done everything.\n"
    "Exit status: 0 all inputs ok, 3 some input failed, 2 bad usage, 5 cancelled (Ctrl-C; results so far kept).\n";

bool is_option(const std::string& a) { return a.size() > 1 && a[0] == '-'; }

[[noreturn]] void print_usage_and_exit() {
  std::cout << kUsage;
  std::exit(0);
}

int parse_int(const std::string& name, const std::string& v, int lo, int hi) {
  try {
    size_t used = 0;
    const long x = std::stol(v, &used);
    if (used == v.size() && x >= lo && x <= hi) return static_cast<int>(x);
  } catch (const std::exception&) {
  }
  usage_error(name + " " + v + ": expected an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
}

// Default output extension of each pipeline's -o file ("" = the runner passes no -o).
std::string default_ext(const std::string& pipeline) {
  if (pipeline == "info" || pipeline == "heat") return "";
  if (pipeline == "factor") return "locus";
  if (pipeline == "param" || pipeline == "perfect-laplacian") return "obj";
  return "ply";
}

// `--merge DIR... [--out DIR] [--json]` (args[0] is "--merge").
RunOptions parse_merge_args(const std::vector<std::string>& args) {
  RunOptions o;
  size_t k = 1;
  for (; k < args.size() && !is_option(args[k]); ++k) o.merge.push_back(args[k]);
  for (; k < args.size(); ++k) {
    if (args[k] == "--json") o.json = true;
    else if (args[k] == "--out" && k + 1 < args.size()) o.out = args[++k];
    else if (args[k].rfind("--out=", 0) == 0) o.out = args[k].substr(6);
    else usage_error("--merge: unexpected argument " + args[k]);
  }
  if (o.merge.empty()) usage_error("--merge needs at least one folder holding shard summaries");
  if (o.out.empty()) o.out = o.merge.front();
  return o;
}

void check_pipeline(const std::string& pipeline, const std::vector<std::string>& commands) {
  if (pipeline == "run" || std::find(commands.begin(), commands.end(), pipeline) == commands.end()) {
    std::string list;
    for (const auto& c : commands) list += (list.empty() ? "" : ", ") + c;
    usage_error("unknown pipeline '" + pipeline + "' (one of: " + list + ")");
  }
}

// One option at args[i] (advancing i past its value): the runner's own, or
// else appended to the pipeline's arguments.
void parse_option(const std::vector<std::string>& args, size_t& i, RunOptions& o) {
  const std::string& a = args[i];
  const size_t eq = a.find('=');
  const bool has_inline = a.rfind("--", 0) == 0 && eq != std::string::npos;
  const std::string name = has_inline ? a.substr(0, eq) : a;
  auto value = [&] {
    if (has_inline) return a.substr(eq + 1);
    if (i + 1 >= args.size()) usage_error(name + " needs a value");
    return args[++i];
  };
  if (name == "--out") {
    o.out = value();
  } else if (name == "--jobs" || name == "-j") {
    o.jobs = parse_int("--jobs", value(), 1, 1024);
  } else if (name == "--threads") {
    o.threads = parse_int("--threads", value(), 1, 4096);
  } else if (name == "--ext") {
    o.ext = value();
  } else if (name == "--json") {
    o.json = true;
  } else if (name == "--recursive" || name == "-r") {
    o.recursive = true;
  } else if (name == "--resume") {
    o.resume = true;
  } else if (name == "--shard") {
    const std::string v = value();
    const size_t slash = v.find('/');
    if (slash == std::string::npos) usage_error("--shard " + v + ": expected K/N, e.g. 2/8");
    o.shards = parse_int("--shard N", v.substr(slash + 1), 1, 1000000);
    o.shard = parse_int("--shard K", v.substr(0, slash), 1, o.shards);
  } else if (name == "-h" || name == "--help") {
    print_usage_and_exit();
  } else if (name == "--preview") {
    // One image per item, named like its other outputs: a path given here
    // would make every item overwrite one file.
    if (has_inline || (i + 1 < args.size() && !is_option(args[i + 1])))
      usage_error("--preview takes no file in locus run: each item's image goes to DIR/<name>.png");
    o.preview = true;
  } else if (name == "-o" || name == "--output") {
    usage_error(name + ": the runner names each output itself (DIR/<name>.<ext>); use --out DIR and --ext EXT");
  } else {
    o.pipeline_args.push_back(a);
  }
}

}  // namespace

[[noreturn]] void usage_error(const std::string& msg) { fail(ErrorCode::BadUsage, "run: " + msg); }

RunOptions parse_run_args(int argc, char** argv, const std::vector<std::string>& commands) {
  const std::vector<std::string> args(argv + 2, argv + argc);  // after "locus run"
  if (!args.empty() && (args[0] == "-h" || args[0] == "--help")) print_usage_and_exit();
  if (!args.empty() && args[0] == "--merge") return parse_merge_args(args);
  if (args.empty() || args[0].empty() || args[0][0] == '-')
    usage_error("expected a PIPELINE (a locus command) first\n" + std::string(kUsage));
  RunOptions o;
  o.pipeline = args[0];
  check_pipeline(o.pipeline, commands);
  size_t i = 1;
  for (; i < args.size() && !is_option(args[i]); ++i) o.inputs.push_back(args[i]);
  for (; i < args.size(); ++i) parse_option(args, i, o);
  if (o.inputs.empty()) usage_error("no input file or folder given (inputs come right after the pipeline name)");
  if (o.out.empty()) usage_error("--out DIR is required");
  if (o.ext.empty()) o.ext = default_ext(o.pipeline);
  if (o.ext == "none") o.ext.clear();
  if (!o.ext.empty() && o.ext[0] == '.') o.ext.erase(0, 1);
  if (o.ext.find('/') != std::string::npos) usage_error("--ext " + o.ext + ": not a file extension");
  return o;
}

}  // namespace locus::runner
