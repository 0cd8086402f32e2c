// summary.json of a `locus run` (see summary.hpp).
#include "tools/runner/summary.hpp"

#include <cstdio>
#include <iostream>

#include "locus/error.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/locus.h"

namespace locus::runner {
namespace {

namespace fs = std::filesystem;

std::string format_seconds(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

void print_table(const Json& summary, const fs::path& path) {
  std::cout << summary["pipeline"].get<std::string>() << " on " << summary["inputs"] << " input(s): "
            << summary["succeeded"] << " ok, " << summary["failed"] << " failed, " << summary["cancelled"]
            << " cancelled, " << summary["not_run"] << " not run";
  if (summary["resumed"].get<size_t>() > 0) std::cout << " (" << summary["resumed"] << " resumed)";
  std::cout << ", in " << format_seconds(summary["seconds"].get<double>()) << " s\n";
  for (const Json& line : summary["items"])
    if (line["status"] != "ok")
      std::cout << "  " << line["status"].get<std::string>() << ": " << line["input"].get<std::string>()
                << (line["error"].is_string() ? " (" + line["error"].get<std::string>() + ")" : "") << "\n";
  if (!summary["ignored"].empty()) {
    std::cout << "  ignored (not .off/.obj/.ply):";
    for (const Json& f : summary["ignored"]) std::cout << " " << f.get<std::string>();
    std::cout << "\n";
  }
  std::cout << "summary: " << path.string() << "\n";
}

}  // namespace

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

Json run_summary(const RunOptions& o, int threads_per_item, const std::vector<std::string>& ignored, bool cancelled,
                 double seconds, Json items) {
  Json summary{{"command", "run"}, {"pipeline", o.pipeline}, {"pipeline_options", o.pipeline_args}};
  summary["ext"] = o.ext;
  summary["out"] = o.out;
  summary["jobs"] = o.jobs;
  summary["threads_per_item"] = threads_per_item;
  summary["shard"] = o.shards > 1 ? Json(std::to_string(o.shard) + "/" + std::to_string(o.shards)) : Json(nullptr);
  summary["ignored"] = ignored;
  summary["stopped"] = cancelled ? Json("cancelled") : Json(nullptr);
  summary["seconds"] = seconds;
  summary["items"] = std::move(items);
  return summary;
}

void write_summary(const RunOptions& o, const Json& summary, const fs::path& path) {
  io::write_file_atomically(path.string(), summary.dump(2) + "\n");
  if (o.json) {
    std::cout << summary.dump(2) << std::endl;
    return;
  }
  print_table(summary, path);
}

}  // namespace locus::runner
