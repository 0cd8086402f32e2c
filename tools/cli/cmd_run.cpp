// `locus run PIPELINE FILE-OR-FOLDER... [pipeline options] --out DIR [--jobs J]
// [--threads N] [--ext EXT] [--json]`: one pipeline (any locus command) over
// many meshes (issue 9 item 4).
//
// Inputs are the arguments between PIPELINE and the first option; a folder
// stands for the mesh files directly inside it (.off .obj .ply, any case),
// sorted by name; other files in a folder are ignored (counted in the summary).
// Every later argument that is not one of the runner's own options goes to
// the pipeline unchanged (--sites 200 --iters 20 ...).
//
// Design: every item runs as a child process of this same executable
// (/proc/self/exe via posix_spawn) with `PIPELINE INPUT [options] --json
// --threads T -o DIR/STEM.EXT`, stdout to a file that becomes the item's
// report and stderr captured into it. A child process isolates what a
// thread cannot: a crash, an abort or a runaway allocation on one hostile file
// costs that item only, and the memory of a finished item is returned to the
// system. The cost, one exec and one mesh load per item, is what the item
// would cost anyway. Children run J at a time with T = max(1, N / J) threads
// each (N = --threads, default all cores), so the machine is not oversubscribed.
//
// Outputs in DIR, per input STEM (the file name without extension; "-2", "-3"
// appended when two inputs share one): STEM.EXT (the pipeline's -o file; EXT
// defaults per pipeline: ply for per-vertex results, obj for param, locus for
// factor (--save), none for info and heat), with --preview STEM.png (the
// pipeline's --preview; hks with several t writes STEM-t0.png, ...), and
// STEM.json, the item report:
// {input, status (ok | failed | crashed | cancelled), exit_status, signal,
// seconds, output, error (last "error:" line of stderr), stderr, result (the
// pipeline's JSON, or null)}. DIR/summary.json lists every item and the counts;
// --json prints it on stdout too, otherwise a short table goes to stdout.
//
// Progress: a one-line bar on stderr (items done / total, items per second,
// ETA) only when stderr is a terminal.
// Ctrl-C (SIGINT) or SIGTERM: no new item starts, running children get SIGINT
// (they stop at their next cancellation check; SIGKILL after 10 s), finished
// results stay, the summary is written with the unfinished items as
// "cancelled" / "not_run", exit status 5. Children run in their own process
// group, so a terminal Ctrl-C reaches them only through the runner, once. A
// second Ctrl-C kills the running children and the runner.
//
// Exit status: 0 every input succeeded; 3 some input failed (bad file,
// numerical failure or crash: each is reported and skipped, the run goes on);
// 2 bad usage of the runner, or every input refused as bad usage by the
// pipeline (its options are wrong: --sites abc); 5 cancelled. A bad-usage
// refusal of some inputs only (--sites 200 on a 19-vertex mesh) is a failed
// input like any other: the run goes on.
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "locus/error.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/locus.h"
#include "tools/cli/cli_common.hpp"

extern char** environ;

namespace locus::cli {
namespace {

namespace fs = std::filesystem;

std::atomic<int> g_stop{0};  // signal number that asked the runner to stop, 0 = none
static_assert(std::atomic<int>::is_always_lock_free);

// Running children, one slot per job (0 = free): the signal handler may kill them.
constexpr int kMaxJobs = 1024;
std::atomic<pid_t> g_children[kMaxJobs];
static_assert(std::atomic<pid_t>::is_always_lock_free);

// First Ctrl-C: ask to stop (the loop forwards SIGINT to the children once).
// Second: kill the children and die by the signal. Only async-signal-safe calls.
extern "C" void on_stop_signal(int sig) {
  if (g_stop.exchange(sig, std::memory_order_relaxed) == 0) return;
  for (auto& c : g_children) {
    const pid_t pid = c.load(std::memory_order_relaxed);
    if (pid > 0) ::kill(pid, SIGKILL);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

struct RunOptions {
  std::string pipeline;
  std::vector<std::string> inputs;
  std::vector<std::string> pipeline_args;
  std::string out;
  int jobs = 1;
  int threads = 0;
  std::string ext;  // "" = the pipeline's default
  bool json = false;
  bool recursive = false;  // --recursive: folders include their subfolders
  bool resume = false;     // --resume: skip items whose report says ok for the same command line
  int shard = 1, shards = 1;  // --shard K/N: every N-th input of the sorted list, from the K-th
  std::vector<std::string> merge;  // --merge DIR...: combine shard summaries, run nothing
  bool preview = false;  // --preview: every item writes DIR/STEM.png (hks with several t: DIR/STEM-tK.png)
};

const char* kUsage =
    "Usage: locus run PIPELINE FILE-OR-FOLDER... [pipeline options] --out DIR [--jobs J] [--threads N]\n"
    "                 [--ext EXT|none] [--preview] [--recursive] [--resume] [--shard K/N] [--json]\n"
    "       locus run --merge DIR... [--out DIR] [--json]\n"
    "Runs `locus PIPELINE` on every input (folders: the .off/.obj/.ply files inside, sorted; with --recursive\n"
    "their subfolders too), J at a time with N/J threads each. Writes DIR/<name>.<EXT> (the pipeline's -o\n"
    "output), DIR/<name>.json (one report per input), with --preview DIR/<name>.png (one image per input),\n"
    "and DIR/summary.json (also on stdout with --json). A\n"
    "failing input is reported and skipped. --resume skips inputs whose report in DIR says ok for the same\n"
    "pipeline and options. --shard K/N runs the K-th of N deterministic parts of the sorted inputs and writes\n"
    "DIR/summary-K-of-N.json; --merge combines the summaries found in the given folders into one\n"
    "(DIR/summary.json of --out, default the first folder), as if one run had done everything.\n"
    "Exit status: 0 all inputs ok, 3 some input failed, 2 bad usage, 5 cancelled (Ctrl-C; results so far kept).\n";

[[noreturn]] void usage_error(const std::string& msg) { fail(ErrorCode::BadUsage, "run: " + msg); }

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

RunOptions parse_run_args(int argc, char** argv, const std::vector<std::string>& commands) {
  RunOptions o;
  std::vector<std::string> args(argv + 2, argv + argc);  // after "locus run"
  if (!args.empty() && (args[0] == "-h" || args[0] == "--help")) {
    std::cout << kUsage;
    std::exit(0);
  }
  if (!args.empty() && args[0] == "--merge") {
    size_t k = 1;
    for (; k < args.size() && !(args[k].size() > 1 && args[k][0] == '-'); ++k) o.merge.push_back(args[k]);
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
  if (args.empty() || args[0].empty() || args[0][0] == '-') usage_error("expected a PIPELINE (a locus command) first\n" + std::string(kUsage));
  o.pipeline = args[0];
  if (o.pipeline == "run" || std::find(commands.begin(), commands.end(), o.pipeline) == commands.end()) {
    std::string list;
    for (const auto& c : commands) list += (list.empty() ? "" : ", ") + c;
    usage_error("unknown pipeline '" + o.pipeline + "' (one of: " + list + ")");
  }
  size_t i = 1;
  for (; i < args.size() && !(args[i].size() > 1 && args[i][0] == '-'); ++i) o.inputs.push_back(args[i]);
  auto value = [&](size_t& k, const std::string& name, const std::string& inline_value, bool has_inline) {
    if (has_inline) return inline_value;
    if (k + 1 >= args.size()) usage_error(name + " needs a value");
    return args[++k];
  };
  for (; i < args.size(); ++i) {
    const std::string& a = args[i];
    const size_t eq = a.find('=');
    const bool has_inline = a.rfind("--", 0) == 0 && eq != std::string::npos;
    const std::string name = has_inline ? a.substr(0, eq) : a;
    const std::string inline_value = has_inline ? a.substr(eq + 1) : "";
    if (name == "--out") {
      o.out = value(i, name, inline_value, has_inline);
    } else if (name == "--jobs" || name == "-j") {
      o.jobs = parse_int("--jobs", value(i, name, inline_value, has_inline), 1, 1024);
    } else if (name == "--threads") {
      o.threads = parse_int("--threads", value(i, name, inline_value, has_inline), 1, 4096);
    } else if (name == "--ext") {
      o.ext = value(i, name, inline_value, has_inline);
    } else if (name == "--json") {
      o.json = true;
    } else if (name == "--recursive" || name == "-r") {
      o.recursive = true;
    } else if (name == "--resume") {
      o.resume = true;
    } else if (name == "--shard") {
      const std::string v = value(i, name, inline_value, has_inline);
      const size_t slash = v.find('/');
      if (slash == std::string::npos) usage_error("--shard " + v + ": expected K/N, e.g. 2/8");
      o.shards = parse_int("--shard N", v.substr(slash + 1), 1, 1000000);
      o.shard = parse_int("--shard K", v.substr(0, slash), 1, o.shards);
    } else if (name == "-h" || name == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else if (name == "--preview") {
      // One image per item, named like its other outputs: a path given here
      // would make every item overwrite one file.
      if (has_inline || (i + 1 < args.size() && !(args[i + 1].size() > 1 && args[i + 1][0] == '-')))
        usage_error("--preview takes no file in locus run: each item's image goes to DIR/<name>.png");
      o.preview = true;
    } else if (name == "-o" || name == "--output") {
      usage_error(name + ": the runner names each output itself (DIR/<name>.<ext>); use --out DIR and --ext EXT");
    } else {
      o.pipeline_args.push_back(a);
    }
  }
  if (o.inputs.empty()) usage_error("no input file or folder given (inputs come right after the pipeline name)");
  if (o.out.empty()) usage_error("--out DIR is required");
  if (o.ext.empty()) o.ext = default_ext(o.pipeline);
  if (o.ext == "none") o.ext.clear();
  if (!o.ext.empty() && o.ext[0] == '.') o.ext.erase(0, 1);
  if (o.ext.find('/') != std::string::npos) usage_error("--ext " + o.ext + ": not a file extension");
  return o;
}

bool is_mesh_file(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e == ".off" || e == ".obj" || e == ".ply";
}

struct Item {
  size_t index = 0;  // position in the sorted list of every input (before --shard)
  std::string input;
  std::string stem;  // unique within DIR
  std::string missing;  // non-empty: the input could not be listed (reported as failed, not run)
  // Result.
  std::string status = "not_run";
  int exit_status = -1, signal = 0;
  double seconds = 0;
  pid_t pid = -1;
  std::chrono::steady_clock::time_point start;
  std::string out_capture, err_capture;  // the child's stdout / stderr, unique temporary files in DIR
  bool resumed = false;  // --resume found an ok report for this item
};

// The files under a folder: directly inside it, or (recursive) at any depth.
// Meshes go to `files`, everything else to `ignored`; an unreadable entry sets ec.
void list_folder(const std::string& in, bool recursive, std::vector<std::string>& files,
                 std::vector<std::string>& ignored, std::error_code& ec) {
  auto take = [&](const fs::directory_entry& e) {
    std::error_code fec;
    if (e.is_directory(fec)) return;
    if (is_mesh_file(e.path())) files.push_back(e.path().string());
    else ignored.push_back(e.path().string());
  };
  if (recursive) {
    for (fs::recursive_directory_iterator it(in, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end;
         it.increment(ec))
      take(*it);
  } else {
    for (fs::directory_iterator it(in, ec), end; !ec && it != end; it.increment(ec)) take(*it);
  }
}

std::vector<Item> expand_inputs(const std::vector<std::string>& inputs, bool recursive,
                                std::vector<std::string>& ignored) {
  std::vector<Item> items;
  ignored.clear();
  for (const std::string& in : inputs) {
    std::error_code ec;
    const fs::file_status st = fs::status(in, ec);
    if (!ec && fs::is_directory(st)) {
      std::vector<std::string> files;
      list_folder(in, recursive, files, ignored, ec);
      if (ec) {
        Item bad;
        bad.input = in;
        bad.missing = in + ": cannot list the folder (" + ec.message() + ")";
        items.push_back(bad);
      }
      std::sort(files.begin(), files.end());
      for (auto& f : files) {
        Item it;
        it.input = f;
        items.push_back(it);
      }
    } else {
      Item it;
      it.input = in;
      if (ec || !fs::exists(st)) it.missing = in + ": no such file or folder";
      items.push_back(it);
    }
  }
  std::sort(ignored.begin(), ignored.end());
  // Unique stems, in input order (before --shard, so every shard names an input alike).
  std::set<std::string> used{"summary"};
  for (size_t k = 0; k < items.size(); ++k) items[k].index = k;
  for (Item& it : items) {
    std::string base = fs::path(it.input).stem().string();
    if (base.empty() || base == "." || base == "..") base = "input";
    std::string stem = base;
    for (int k = 2; used.count(stem); ++k) stem = base + "-" + std::to_string(k);
    used.insert(stem);
    it.stem = stem;
  }
  return items;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The last "error:" line of a child's stderr, without the "locus: error: " prefix.
std::string last_error_line(const std::string& err) {
  std::string found;
  std::istringstream is(err);
  for (std::string line; std::getline(is, line);) {
    const size_t at = line.find("error: ");
    if (at != std::string::npos) found = line.substr(at + 7);
  }
  return found;
}

std::string human_seconds(double s) {
  if (!(s >= 0) || s > 1e7) return "?";
  char buf[32];
  if (s < 60) {
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  } else if (s < 3600) {
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s) / 3600, static_cast<int>(s) / 60 % 60);
  }
  return buf;
}

class Progress {
 public:
  explicit Progress(size_t total) : total_(total), on_(::isatty(STDERR_FILENO) == 1) {}
  void draw(size_t done, size_t running, size_t failed, double elapsed) {
    if (!on_) return;
    // Redraw on every completed item, otherwise at most 4 times a second.
    if (done == last_done_ && elapsed - last_draw_ < 0.25) return;
    last_done_ = done;
    last_draw_ = elapsed;
    constexpr int kWidth = 30;
    const int fill = total_ ? static_cast<int>(kWidth * done / total_) : kWidth;
    const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0;
    const std::string eta = done > 0 && done < total_ ? human_seconds((total_ - done) / rate) : (done == total_ ? "0s" : "?");
    std::fprintf(stderr, "\r[%s%s] %zu/%zu  %.2f items/s  ETA %s  running %zu  failed %zu \x1b[K",
                 std::string(static_cast<size_t>(fill), '#').c_str(), std::string(static_cast<size_t>(kWidth - fill), '.').c_str(),
                 done, total_, rate, eta.c_str(), running, failed);
    std::fflush(stderr);
    drawn_ = true;
  }
  void finish() {
    if (on_ && drawn_) std::fputc('\n', stderr);
    drawn_ = false;
  }
  // Writes a log line without breaking the bar.
  void line(const std::string& text) {
    if (on_ && drawn_) std::fputs("\r\x1b[K", stderr);
    std::fprintf(stderr, "locus: %s\n", text.c_str());
  }

 private:
  size_t total_;
  bool on_;
  bool drawn_ = false;
  size_t last_done_ = static_cast<size_t>(-1);
  double last_draw_ = 0;
};

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("/proc/self/exe") : p.string();
}

// A unique, empty capture file in DIR: two runs over one folder never share one.
std::string make_capture(const fs::path& out_dir, const std::string& stem, const char* kind) {
  std::string tmpl = (out_dir / ("." + stem + "." + kind + ".XXXXXX")).string();
  const int fd = ::mkostemp(tmpl.data(), O_CLOEXEC);
  if (fd < 0) fail(ErrorCode::BadInput, "run: cannot create a capture file in " + out_dir.string() + ": " + std::strerror(errno));
  ::close(fd);
  return tmpl;
}

pid_t spawn_item(const std::string& exe, const RunOptions& o, Item& it, const fs::path& out_dir,
                 int threads_per_item) {
  std::vector<std::string> args = {exe, o.pipeline, it.input};
  args.insert(args.end(), o.pipeline_args.begin(), o.pipeline_args.end());
  args.insert(args.end(), {"--json", "--threads", std::to_string(threads_per_item)});
  if (!o.ext.empty()) {
    const std::string out = (out_dir / (it.stem + "." + o.ext)).string();
    // factor writes its factor with --save; every other pipeline with -o.
    if (o.pipeline == "factor") {
      args.insert(args.end(), {"--save", out});
    } else {
      args.insert(args.end(), {"-o", out});
    }
  }
  if (o.preview) args.insert(args.end(), {"--preview", (out_dir / (it.stem + ".png")).string()});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  it.out_capture = make_capture(out_dir, it.stem, "stdout");
  it.err_capture = make_capture(out_dir, it.stem, "stderr");
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, it.out_capture.c_str(), O_WRONLY | O_TRUNC, 0);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, it.err_capture.c_str(), O_WRONLY | O_TRUNC, 0);
  // The child starts with default SIGINT handling (its own handler then turns Ctrl-C into exit 5).
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t def;
  sigemptyset(&def);
  sigaddset(&def, SIGINT);
  sigaddset(&def, SIGTERM);
  posix_spawnattr_setsigdefault(&attr, &def);
  // Own process group: a terminal Ctrl-C reaches the runner only, which forwards
  // exactly one SIGINT (a child's second SIGINT would kill it before it can stop cleanly).
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, exe.c_str(), &fa, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) fail(ErrorCode::Internal, "run: cannot start " + exe + ": " + std::strerror(rc));
  return pid;
}

Json summary_line(const Item& it, const fs::path& report_path, const Json& report);

// Reads the child's stdout/stderr, writes DIR/STEM.json, returns the item's summary line.
Json finish_item(Item& it, const RunOptions& o, const fs::path& out_dir) {
  std::string out = it.out_capture.empty() ? "" : slurp(it.out_capture);
  std::string err = it.missing.empty() ? slurp(it.err_capture) : it.missing;
  std::error_code ec;
  if (!it.out_capture.empty()) fs::remove(it.out_capture, ec);
  if (!it.err_capture.empty()) fs::remove(it.err_capture, ec);
  Json result = nullptr;
  if (!out.empty()) {
    try {
      result = Json::parse(out);
    } catch (const std::exception&) {
      result = nullptr;  // a crash mid-output: the raw text goes into the report instead
    }
  }
  std::string error = it.missing.empty() ? last_error_line(err) : it.missing;
  if (it.status == "crashed" && error.empty()) error = "killed by signal " + std::to_string(it.signal);
  constexpr size_t kMaxStderr = 64 * 1024;  // a runaway log must not blow up the report
  if (err.size() > kMaxStderr) err = "..." + err.substr(err.size() - kMaxStderr);

  std::string output;
  if (!o.ext.empty() && it.status == "ok") {
    const fs::path p = out_dir / (it.stem + "." + o.ext);
    if (fs::exists(p, ec)) output = p.string();
  }
  Json report{{"input", it.input}, {"pipeline", o.pipeline}, {"pipeline_options", o.pipeline_args}, {"ext", o.ext},
              {"status", it.status}, {"exit_status", it.exit_status}};
  report["signal"] = it.signal;
  report["seconds"] = it.seconds;
  report["output"] = output.empty() ? Json(nullptr) : Json(output);
  report["preview"] = result.is_object() && result.contains("preview") ? result["preview"] : Json(nullptr);
  report["error"] = error.empty() ? Json(nullptr) : Json(error);
  report["stderr"] = err;
  if (result.is_null() && !out.empty()) report["stdout"] = out.substr(0, kMaxStderr);
  report["result"] = result;
  const fs::path report_path = out_dir / (it.stem + ".json");
  io::write_file_atomically(report_path.string(), report.dump(2) + "\n");
  return summary_line(it, report_path, report);
}

Json summary_line(const Item& it, const fs::path& report_path, const Json& report) {
  Json line{{"index", it.index}, {"input", it.input}, {"status", it.status}, {"exit_status", it.exit_status},
            {"seconds", it.seconds}};
  line["report"] = report_path.string();
  line["output"] = report.value("output", Json(nullptr));
  line["preview"] = report.value("preview", Json(nullptr));
  line["error"] = report.value("error", Json(nullptr));
  line["resumed"] = it.resumed;
  return line;
}

// --resume: the item's report in DIR says ok for this input, pipeline, options and extension.
bool resume_item(Item& it, const RunOptions& o, const fs::path& out_dir, Json& line) {
  const fs::path report_path = out_dir / (it.stem + ".json");
  std::error_code ec;
  if (!it.missing.empty() || !fs::is_regular_file(report_path, ec)) return false;
  Json report;
  try {
    report = Json::parse(slurp(report_path));
  } catch (const std::exception&) {
    return false;  // unreadable report: run the item again
  }
  if (!report.is_object() || report.value("status", "") != "ok" || report.value("input", "") != it.input ||
      report.value("pipeline", "") != o.pipeline || report.value("ext", "") != o.ext ||
      report.value("pipeline_options", Json::array()) != Json(o.pipeline_args) ||
      report.value("preview", Json(nullptr)).is_null() == o.preview)
    return false;
  if (report["output"].is_string() && !fs::exists(report["output"].get<std::string>(), ec)) return false;
  it.status = "ok";
  it.exit_status = 0;
  it.seconds = report.value("seconds", 0.0);
  it.resumed = true;
  line = summary_line(it, report_path, report);
  return true;
}

// Counts of a summary's items and its exit status (0 all ok, 5 cancelled, 2
// every item refused as bad usage, 3 some failed), written into it.
int count_summary(Json& summary, bool cancelled, size_t usage_failures) {
  size_t ok = 0, failed = 0, n_cancelled = 0, not_run = 0, resumed = 0;
  for (const Json& line : summary["items"]) {
    const std::string s = line.value("status", "");
    if (s == "ok") ++ok;
    else if (s == "cancelled") ++n_cancelled;
    else if (s == "not_run") ++not_run;
    else ++failed;
    resumed += line.value("resumed", false) ? 1 : 0;
  }
  const size_t n = summary["items"].size();
  int status = 0;
  if (cancelled) status = static_cast<int>(ErrorCode::Cancelled);
  else if (n > 0 && usage_failures == n) status = static_cast<int>(ErrorCode::BadUsage);
  else if (failed > 0) status = static_cast<int>(ErrorCode::BadInput);
  summary["inputs"] = n;
  summary["ignored_files"] = summary["ignored"].size();
  summary["succeeded"] = ok;
  summary["failed"] = failed;
  summary["cancelled"] = n_cancelled;
  summary["not_run"] = not_run;
  summary["resumed"] = resumed;
  summary["exit_status"] = status;
  summary["version"] = locus_version(nullptr, nullptr, nullptr);
  return status;
}

void print_summary(const RunOptions& o, const Json& summary, const fs::path& summary_path) {
  if (o.json) {
    std::cout << summary.dump(2) << std::endl;
    return;
  }
  std::cout << summary["pipeline"].get<std::string>() << " on " << summary["inputs"] << " input(s): "
            << summary["succeeded"] << " ok, " << summary["failed"] << " failed, " << summary["cancelled"]
            << " cancelled, " << summary["not_run"] << " not run";
  if (summary["resumed"].get<size_t>() > 0) std::cout << " (" << summary["resumed"] << " resumed)";
  std::cout << ", in " << format_number(summary["seconds"].get<double>()) << " s\n";
  for (const Json& line : summary["items"])
    if (line["status"] != "ok")
      std::cout << "  " << line["status"].get<std::string>() << ": " << line["input"].get<std::string>()
                << (line["error"].is_string() ? " (" + line["error"].get<std::string>() + ")" : "") << "\n";
  if (!summary["ignored"].empty()) {
    std::cout << "  ignored (not .off/.obj/.ply):";
    for (const Json& f : summary["ignored"]) std::cout << " " << f.get<std::string>();
    std::cout << "\n";
  }
  std::cout << "summary: " << summary_path.string() << "\n";
}

// The summaries of one folder: its shard summaries, or else its summary.json.
std::vector<fs::path> summaries_in(const std::string& dir) {
  std::vector<fs::path> shards;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind("summary-", 0) == 0 && name.find("-of-") != std::string::npos && it->path().extension() == ".json")
      shards.push_back(it->path());
  }
  if (ec) fail(ErrorCode::BadInput, "run --merge: cannot list " + dir + " (" + ec.message() + ")");
  std::sort(shards.begin(), shards.end());
  if (shards.empty() && fs::is_regular_file(fs::path(dir) / "summary.json", ec)) shards.push_back(fs::path(dir) / "summary.json");
  if (shards.empty()) fail(ErrorCode::BadInput, "run --merge: " + dir + " holds no summary.json or summary-K-of-N.json");
  return shards;
}

// --merge DIR...: one summary of every item of the shards' runs, in the order
// of the unsharded run. Refuses summaries of different pipelines or options,
// and a missing or repeated shard (a partial merge would silently drop items).
int merge_summaries(const RunOptions& o) {
  std::vector<Json> parts;
  for (const std::string& dir : o.merge)
    for (const fs::path& p : summaries_in(dir)) {
      try {
        parts.push_back(Json::parse(slurp(p)));
      } catch (const std::exception& e) {
        fail(ErrorCode::BadInput, "run --merge: " + p.string() + " is not valid JSON (" + e.what() + ")");
      }
      parts.back()["_path"] = p.string();
    }
  const Json& first = parts.front();
  std::set<std::string> seen_shards;
  int shards = 0;
  Json items = Json::array();
  std::set<std::string> ignored;
  double seconds = 0;
  bool cancelled = false;
  for (const Json& part : parts) {
    const std::string where = part["_path"].get<std::string>();
    if (part.value("command", "") != "run" || !part.contains("items"))
      fail(ErrorCode::BadInput, "run --merge: " + where + " is not a locus run summary");
    if (part["pipeline"] != first["pipeline"] || part["pipeline_options"] != first["pipeline_options"] ||
        part.value("ext", Json()) != first.value("ext", Json()))
      fail(ErrorCode::BadInput, "run --merge: " + where + " ran another pipeline or other options than " +
                                    first["_path"].get<std::string>());
    const std::string shard = part["shard"].is_string() ? part["shard"].get<std::string>() : "1/1";
    const int n = std::stoi(shard.substr(shard.find('/') + 1));
    if (shards != 0 && n != shards) fail(ErrorCode::BadInput, "run --merge: " + where + " is shard " + shard + " of another split");
    shards = n;
    if (!seen_shards.insert(shard).second) fail(ErrorCode::BadInput, "run --merge: shard " + shard + " given twice");
    for (const Json& line : part["items"]) items.push_back(line);
    for (const Json& f : part["ignored"]) ignored.insert(f.get<std::string>());
    seconds = std::max(seconds, part.value("seconds", 0.0));
    cancelled = cancelled || part["stopped"].is_string();
  }
  for (int k = 1; k <= shards; ++k)
    if (!seen_shards.count(std::to_string(k) + "/" + std::to_string(shards)))
      fail(ErrorCode::BadInput, "run --merge: shard " + std::to_string(k) + "/" + std::to_string(shards) + " is missing");
  std::sort(items.begin(), items.end(),
            [](const Json& a, const Json& b) { return a["index"].get<size_t>() < b["index"].get<size_t>(); });
  Json summary{{"command", "run"}, {"pipeline", first["pipeline"]}, {"pipeline_options", first["pipeline_options"]}};
  summary["ext"] = first.value("ext", Json(""));
  summary["out"] = o.out;
  summary["jobs"] = first["jobs"];
  summary["threads_per_item"] = first["threads_per_item"];
  summary["shard"] = nullptr;
  summary["merged_from"] = shards;
  summary["ignored"] = std::vector<std::string>(ignored.begin(), ignored.end());
  summary["stopped"] = cancelled ? Json("cancelled") : Json(nullptr);
  summary["seconds"] = seconds;
  summary["items"] = items;
  size_t usage_failures = 0;
  for (const Json& line : items) usage_failures += line["exit_status"] == static_cast<int>(ErrorCode::BadUsage);
  const int status = count_summary(summary, cancelled, usage_failures);
  const fs::path summary_path = fs::path(o.out) / "summary.json";
  io::write_file_atomically(summary_path.string(), summary.dump(2) + "\n");
  print_summary(o, summary, summary_path);
  return status;
}

}  // namespace

int run_pipeline_runner(int argc, char** argv, const std::vector<std::string>& commands) {
  const RunOptions o = parse_run_args(argc, argv, commands);
  const fs::path out_dir = o.out;
  {
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec || !fs::is_directory(out_dir)) usage_error("--out " + o.out + ": cannot create the folder (" + ec.message() + ")");
  }
  if (!o.merge.empty()) return merge_summaries(o);
  std::vector<std::string> ignored;
  std::vector<Item> items = expand_inputs(o.inputs, o.recursive, ignored);
  if (o.shards > 1) {  // a deterministic split of the sorted inputs: every N-th from the K-th
    std::vector<Item> mine;
    for (Item& it : items)
      if (it.index % static_cast<size_t>(o.shards) == static_cast<size_t>(o.shard - 1)) mine.push_back(std::move(it));
    items = std::move(mine);
  }
  const int total_threads = o.threads > 0 ? o.threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int per_item = std::max(1, total_threads / o.jobs);
  const std::string exe = self_exe();

  g_stop.store(0);
  for (auto& c : g_children) c.store(0);
  auto prev_int = std::signal(SIGINT, on_stop_signal);
  auto prev_term = std::signal(SIGTERM, on_stop_signal);

  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  Progress bar(items.size());
  std::vector<Json> lines(items.size());
  size_t next = 0, done = 0, failed = 0;
  std::vector<size_t> running;
  size_t usage_failures = 0;
  bool forwarded = false;
  std::chrono::steady_clock::time_point forwarded_at;

  auto complete = [&](size_t k) {
    lines[k] = finish_item(items[k], o, out_dir);
    ++done;
    if (items[k].status != "ok" && items[k].status != "cancelled") {
      ++failed;
      bar.line(items[k].input + ": " + items[k].status + " (" +
               (lines[k]["error"].is_null() ? std::string("exit ") + std::to_string(items[k].exit_status)
                                            : lines[k]["error"].get<std::string>()) +
               ")");
    }
  };

  if (o.resume)
    for (size_t k = 0; k < items.size(); ++k)
      if (resume_item(items[k], o, out_dir, lines[k])) ++done;
  while (true) {
    const bool stopping = g_stop.load() != 0;
    // Start items while there is room.
    while (!stopping && running.size() < static_cast<size_t>(o.jobs) && next < items.size()) {
      Item& it = items[next];
      if (it.resumed) {
        ++next;
        continue;
      }
      if (!it.missing.empty()) {
        it.status = "failed";
        it.exit_status = static_cast<int>(ErrorCode::BadInput);
        complete(next++);
        continue;
      }
      it.start = std::chrono::steady_clock::now();
      it.pid = spawn_item(exe, o, it, out_dir, per_item);
      for (auto& c : g_children) {
        pid_t free_slot = 0;
        if (c.compare_exchange_strong(free_slot, it.pid)) break;
      }
      running.push_back(next++);
    }
    if (running.empty() && (stopping || next >= items.size())) break;
    if (stopping && !forwarded) {
      // Ask running children to stop (a terminal Ctrl-C reached them already; SIGTERM or kill -INT did not).
      for (size_t k : running) ::kill(items[k].pid, SIGINT);
      forwarded = true;
      forwarded_at = std::chrono::steady_clock::now();
    }
    if (forwarded && std::chrono::steady_clock::now() - forwarded_at > std::chrono::seconds(10)) {
      for (size_t k : running) ::kill(items[k].pid, SIGKILL);
      forwarded_at = std::chrono::steady_clock::now();
    }
    // Reap whatever finished.
    bool reaped = false;
    for (size_t r = 0; r < running.size();) {
      Item& it = items[running[r]];
      int ws = 0;
      const pid_t got = ::waitpid(it.pid, &ws, WNOHANG);
      if (got == 0 || (got < 0 && errno == EINTR)) {
        ++r;
        continue;
      }
      it.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - it.start).count();
      for (auto& c : g_children) {
        pid_t mine = it.pid;
        if (c.compare_exchange_strong(mine, 0)) break;
      }
      if (got > 0 && WIFEXITED(ws)) {
        it.exit_status = WEXITSTATUS(ws);
        it.status = it.exit_status == 0                                           ? "ok"
                    : it.exit_status == static_cast<int>(ErrorCode::Cancelled) ? "cancelled"
                                                                                 : "failed";
        if (it.exit_status == static_cast<int>(ErrorCode::BadUsage)) ++usage_failures;
      } else if (got > 0 && WIFSIGNALED(ws)) {
        it.signal = WTERMSIG(ws);
        it.status = forwarded && (it.signal == SIGINT || it.signal == SIGKILL) ? "cancelled" : "crashed";
      } else {
        it.status = "crashed";
      }
      complete(running[r]);
      running.erase(running.begin() + static_cast<std::ptrdiff_t>(r));
      reaped = true;
    }
    bar.draw(done, running.size(), failed, elapsed());
    if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  bar.finish();
  std::signal(SIGINT, prev_int);
  std::signal(SIGTERM, prev_term);

  const bool cancelled = g_stop.load() != 0;
  Json item_list = Json::array();
  for (size_t k = 0; k < items.size(); ++k) {
    if (lines[k].is_null())
      lines[k] = {{"index", items[k].index}, {"input", items[k].input}, {"status", items[k].status},
                  {"exit_status", nullptr}, {"seconds", 0.0}, {"report", nullptr}, {"output", nullptr},
                  {"error", nullptr}, {"resumed", false}};
    item_list.push_back(lines[k]);
  }
  Json summary{{"command", "run"}, {"pipeline", o.pipeline}, {"pipeline_options", o.pipeline_args}};
  summary["ext"] = o.ext;
  summary["out"] = o.out;
  summary["jobs"] = o.jobs;
  summary["threads_per_item"] = per_item;
  summary["shard"] = o.shards > 1 ? Json(std::to_string(o.shard) + "/" + std::to_string(o.shards)) : Json(nullptr);
  summary["ignored"] = ignored;
  summary["stopped"] = cancelled ? Json("cancelled") : Json(nullptr);
  summary["seconds"] = elapsed();
  summary["items"] = item_list;
  const int status = count_summary(summary, cancelled, usage_failures);
  const fs::path summary_path =
      out_dir / (o.shards > 1 ? "summary-" + std::to_string(o.shard) + "-of-" + std::to_string(o.shards) + ".json"
                              : std::string("summary.json"));
  io::write_file_atomically(summary_path.string(), summary.dump(2) + "\n");
  print_summary(o, summary, summary_path);
  if (status == static_cast<int>(ErrorCode::BadUsage))
    std::cerr << "locus: error: run: " << o.pipeline << " refused its options on every input (see " << summary_path.string()
              << ")\n";
  if (cancelled) std::cerr << "locus: error: cancelled\n";
  return status;
}

}  // namespace locus::cli
