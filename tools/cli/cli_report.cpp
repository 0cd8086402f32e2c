// The report of a command (cli_report.hpp): the JSON every command prints
// with --json, its timings, and the log lines on stderr.
#include "tools/cli/cli_report.hpp"

#include <oneapi/tbb/global_control.h>

#include <iostream>
#include <vector>

#include "locus/locus.h"

namespace locus::cli {
namespace {

std::string g_tool = "locus";

// Preview images this command wrote (write_preview), for the JSON key `preview`.
std::vector<std::string> g_previews;

// For the `timings` every command reports: when the command started, and the
// input's load and subdivision times (load_input).
Stopwatch g_command_clock;
double g_load_s = 0, g_subdivide_s = 0;

}  // namespace

void report_begin(const std::string& tool_name) {
  g_tool = tool_name;
  g_previews.clear();
  g_load_s = g_subdivide_s = 0;
  g_command_clock.restart();
}

void report_input(double load_s, double subdivide_s) {
  g_load_s = load_s;
  g_subdivide_s = subdivide_s;
}

void report_preview(const std::string& path) { g_previews.push_back(path); }

Json timings(const MeshInput& in, std::initializer_list<std::pair<const char*, double>> phases) {
  Json t{{"load_s", in.load_s}, {"subdivide_s", in.subdivide_s}};
  for (const auto& [key, seconds] : phases) t[key] = seconds;
  return t;
}

void emit(const CommonOptions& opt, const Json& result, const std::function<void(std::ostream&)>& human) {
  if (opt.json) {
    // Keys every command's JSON has: the version that made
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

}  // namespace locus::cli
