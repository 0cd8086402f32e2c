// `locus run --merge` (see merge.hpp).
#include "tools/runner/merge.hpp"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "locus/error.hpp"
#include "tools/runner/out_files.hpp"
#include "tools/runner/summary.hpp"

namespace locus::runner {
namespace {

namespace fs = std::filesystem;

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
  if (shards.empty() && fs::is_regular_file(fs::path(dir) / "summary.json", ec))
    shards.push_back(fs::path(dir) / "summary.json");
  if (shards.empty()) fail(ErrorCode::BadInput, "run --merge: " + dir + " holds no summary.json or summary-K-of-N.json");
  return shards;
}

// Every summary of every folder, parsed, each with its path under "_path".
std::vector<Json> read_parts(const std::vector<std::string>& dirs) {
  std::vector<Json> parts;
  for (const std::string& dir : dirs)
    for (const fs::path& p : summaries_in(dir)) {
      try {
        parts.push_back(Json::parse(slurp(p)));
      } catch (const std::exception& e) {
        fail(ErrorCode::BadInput, "run --merge: " + p.string() + " is not valid JSON (" + e.what() + ")");
      }
      parts.back()["_path"] = p.string();
    }
  return parts;
}

// What the parts add up to.
struct Merged {
  Json items = Json::array();
  std::set<std::string> ignored;
  double seconds = 0;
  bool cancelled = false;
  int shards = 0;
};

// Checks one part against the first and adds its items; `seen` collects shard names.
void add_part(const Json& part, const Json& first, std::set<std::string>& seen, Merged& m) {
  const std::string where = part["_path"].get<std::string>();
  if (part.value("command", "") != "run" || !part.contains("items"))
    fail(ErrorCode::BadInput, "run --merge: " + where + " is not a locus run summary");
  if (part["pipeline"] != first["pipeline"] || part["pipeline_options"] != first["pipeline_options"] ||
      part.value("ext", Json()) != first.value("ext", Json()))
    fail(ErrorCode::BadInput, "run --merge: " + where + " ran another pipeline or other options than " +
                                  first["_path"].get<std::string>());
  const std::string shard = part["shard"].is_string() ? part["shard"].get<std::string>() : "1/1";
  const int n = std::stoi(shard.substr(shard.find('/') + 1));
  if (m.shards != 0 && n != m.shards)
    fail(ErrorCode::BadInput, "run --merge: " + where + " is shard " + shard + " of another split");
  m.shards = n;
  if (!seen.insert(shard).second) fail(ErrorCode::BadInput, "run --merge: shard " + shard + " given twice");
  for (const Json& line : part["items"]) m.items.push_back(line);
  for (const Json& f : part["ignored"]) m.ignored.insert(f.get<std::string>());
  m.seconds = std::max(m.seconds, part.value("seconds", 0.0));
  m.cancelled = m.cancelled || part["stopped"].is_string();
}

}  // namespace

int merge_summaries(const RunOptions& o) {
  const std::vector<Json> parts = read_parts(o.merge);
  const Json& first = parts.front();
  std::set<std::string> seen;
  Merged m;
  for (const Json& part : parts) add_part(part, first, seen, m);
  for (int k = 1; k <= m.shards; ++k)
    if (!seen.count(std::to_string(k) + "/" + std::to_string(m.shards)))
      fail(ErrorCode::BadInput,
           "run --merge: shard " + std::to_string(k) + "/" + std::to_string(m.shards) + " is missing");
  std::sort(m.items.begin(), m.items.end(),
            [](const Json& a, const Json& b) { return a["index"].get<size_t>() < b["index"].get<size_t>(); });
  Json summary{{"command", "run"}, {"pipeline", first["pipeline"]}, {"pipeline_options", first["pipeline_options"]}};
  summary["ext"] = first.value("ext", Json(""));
  summary["out"] = o.out;
  summary["jobs"] = first["jobs"];
  summary["threads_per_item"] = first["threads_per_item"];
  summary["shard"] = nullptr;
  summary["merged_from"] = m.shards;
  summary["ignored"] = std::vector<std::string>(m.ignored.begin(), m.ignored.end());
  summary["stopped"] = m.cancelled ? Json("cancelled") : Json(nullptr);
  summary["seconds"] = m.seconds;
  summary["items"] = m.items;
  size_t usage_failures = 0;
  for (const Json& line : m.items) usage_failures += line["exit_status"] == static_cast<int>(ErrorCode::BadUsage);
  const int status = count_summary(summary, m.cancelled, usage_failures);
  write_summary(o, summary, summary_path(o.out, 1, 1));
  return status;
}

}  // namespace locus::runner
