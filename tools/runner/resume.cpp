// --resume (see resume.hpp). A report is trusted only for the exact command
// line that produced it: another option, extension or --preview is another
// result, so the item runs again.
#include "tools/runner/resume.hpp"

#include <exception>
#include <system_error>

#include "tools/runner/item_report.hpp"
#include "tools/runner/out_files.hpp"

namespace locus::runner {

namespace fs = std::filesystem;

bool resume_item(Item& it, const RunOptions& o, const fs::path& out_dir, Json& line) {
  const fs::path path = report_path(out_dir, it.stem);
  std::error_code ec;
  if (!it.missing.empty() || !fs::is_regular_file(path, ec)) return false;
  Json report;
  try {
    report = Json::parse(slurp(path));
  } catch (const std::exception&) {
    return false;  // unreadable report: run the item again
  }
  if (!report_matches(report, it.input, o) || report.value("status", "") != "ok") return false;
  if (report["output"].is_string() && !fs::exists(report["output"].get<std::string>(), ec)) return false;
  it.status = "ok";
  it.exit_status = 0;
  it.seconds = report.value("seconds", 0.0);
  it.resumed = true;
  line = summary_line(it, path, report);
  return true;
}

}  // namespace locus::runner
