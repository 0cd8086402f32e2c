// What a command reports (DESIGN.md "Every CLI subcommand accepts --json"):
// one JSON object on stdout with --json, else a human summary; log lines on
// stderr. Every report has the keys `output`, `preview`, `threads`,
// `version` and `timings`, whose `load_s`, `subdivide_s` and `total_s` every
// command has: timings() builds that object from the input and the command's
// own phases, emit() completes and prints the report.
#pragma once
#include <nlohmann/json.hpp>

#include <functional>
#include <initializer_list>
#include <iosfwd>
#include <string>
#include <utility>

#include "locus/engine/heat_time.hpp"
#include "locus/engine/mesh_input.hpp"
#include "tools/cli/cli_command_table.hpp"

namespace locus::cli {

// JSON objects keep their keys in insertion order, so outputs read top-down
// (command, input, sizes, timings, quality) rather than alphabetically.
using Json = nlohmann::ordered_json;

// A command's `timings`: the input's load_s and subdivide_s, then `phases` in
// order (seconds); emit() adds total_s (command start to the report) unless a
// phase is named so.
Json timings(const MeshInput& in, std::initializer_list<std::pair<const char*, double>> phases = {});

// With --json prints `result` as one JSON object on stdout; otherwise calls
// `human` with stdout.
void emit(const CommonOptions& opt, const Json& result, const std::function<void(std::ostream&)>& human);

// A log line on stderr ("<tool>: <text>"); stdout stays reserved for results.
void log(const std::string& text);

// The report's bookkeeping, kept by the CommandTable and the helpers that
// write files: the tool's name for log lines, when the command started, the
// input's load and subdivision times (load_input) and the previews written.
void report_begin(const std::string& tool_name);
void report_input(double load_s, double subdivide_s);
void report_preview(const std::string& path);

// A number for messages: %.6g ("1e+12", "0.000134", "nan"), not std::to_string's fixed notation.
using locus::format_number;

}  // namespace locus::cli
