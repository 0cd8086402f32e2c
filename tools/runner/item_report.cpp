// The report of one `locus run` item (see item_report.hpp). The child's stdout
// is the pipeline's --json object; a crash mid-output leaves text that is not
// JSON, which goes into the report raw instead.
#include "tools/runner/item_report.hpp"

#include <sstream>
#include <string>
#include <system_error>

#include "locus/io/atomic_file_write.hpp"
#include "tools/runner/out_files.hpp"

namespace locus::runner {
namespace {

namespace fs = std::filesystem;

constexpr size_t kMaxStderr = 64 * 1024;  // a runaway log must not blow up the report

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

Json parse_result(const std::string& out) {
  if (out.empty()) return nullptr;
  try {
    return Json::parse(out);
  } catch (const std::exception&) {
    return nullptr;
  }
}

}  // namespace

Json finish_item(Item& it, const RunOptions& o, const fs::path& out_dir) {
  const std::string out = it.out_capture.empty() ? "" : slurp(it.out_capture);
  std::string err = it.missing.empty() ? slurp(it.err_capture) : it.missing;
  std::error_code ec;
  if (!it.out_capture.empty()) fs::remove(it.out_capture, ec);
  if (!it.err_capture.empty()) fs::remove(it.err_capture, ec);
  const Json result = parse_result(out);
  std::string error = it.missing.empty() ? last_error_line(err) : it.missing;
  if (it.status == "crashed" && error.empty()) error = "killed by signal " + std::to_string(it.signal);
  if (err.size() > kMaxStderr) err = "..." + err.substr(err.size() - kMaxStderr);

  std::string output;
  if (!o.ext.empty() && it.status == "ok") {
    const fs::path p = output_path(out_dir, it.stem, o.ext);
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
  const fs::path path = report_path(out_dir, it.stem);
  io::write_file_atomically(path.string(), report.dump(2) + "\n");
  return summary_line(it, path, report);
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

bool report_matches(const Json& report, const std::string& input, const RunOptions& o) {
  return report.is_object() && report.value("input", "") == input && report.value("pipeline", "") == o.pipeline &&
         report.value("ext", "") == o.ext &&
         report.value("pipeline_options", Json::array()) == Json(o.pipeline_args) &&
         report.value("preview", Json(nullptr)).is_null() != o.preview;
}

Json unreported_line(const Item& it) {
  return {{"index", it.index}, {"input", it.input},   {"status", it.status},  {"exit_status", nullptr},
          {"seconds", 0.0},    {"report", nullptr},   {"output", nullptr},    {"error", nullptr},
          {"resumed", false}};
}

}  // namespace locus::runner
