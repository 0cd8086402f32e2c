// What summary.json may claim (see report_check.hpp). Reports are compared by
// what makes a result (input, pipeline, options, extension, --preview) and by
// status, not by timings: two runs of one input with one set of options give
// the same result, so either's report is this run's.
#include "tools/runner/report_check.hpp"

#include <exception>
#include <string>

#include "tools/runner/item_report.hpp"
#include "tools/runner/out_files.hpp"

namespace locus::runner {

void confirm_reports(std::vector<Json>& lines, const std::vector<Item>& items, const RunOptions& o) {
  for (size_t k = 0; k < lines.size(); ++k) {
    Json& line = lines[k];
    if (line.is_null() || !line["report"].is_string()) continue;
    const std::string path = line["report"].get<std::string>();
    Json report;
    try {
      report = Json::parse(slurp(path));
    } catch (const std::exception&) {
      report = nullptr;
    }
    if (report_matches(report, items[k].input, o) && report.value("status", "") == line.value("status", "")) continue;
    std::string why = path + " was removed or replaced by another run";
    if (report.is_object() && report["input"].is_string() && report["input"] != items[k].input)
      why += " (it now reports " + report["input"].get<std::string>() + ")";
    line["status"] = "overwritten";
    line["report"] = nullptr;
    line["output"] = nullptr;
    line["preview"] = nullptr;
    line["error"] = why;
  }
}

}  // namespace locus::runner
