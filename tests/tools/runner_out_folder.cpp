// `locus run` and its --out folder (tools/runner/out_folder_lock.cpp): a
// folder holds the results of one set of options. A run with other options is
// refused with exit 2, a message naming the folder, both option sets and what
// to do, whether the other run is still writing or has finished; nothing of
// the refused run reaches the folder. Runs with the same options share it.
// summary.json lists only reports that still hold this run's results.
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <string>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/runner_support.hpp"

using namespace locus::test_cli;
using nlohmann::json;

namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("runner: a run with other options into a folder of another run is refused, exit 2") {
  if (!have_locus()) return;
  Scratch dir("runner-lock"), cap("runner-lock-a");
  const fs::path in = dir.path / "in";
  fs::create_directories(in);
  for (const char* name : {"m1.off", "m2.off", "m3.off"})
    locus::write_mesh((in / name).string(), locus::make_icosphere(4));  // 2562 vertices
  const std::string out = dir / "out";
  auto cvt = [&](const std::string& sites, std::vector<std::string> extra) {
    std::vector<std::string> a = {"run", "cvt", in.string(), "--sites", sites, "--iters", "40", "--out", out,
                                  "--jobs", "1", "--threads", "1", "--json"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const pid_t first = start_locus(cap, cvt("100", {}));
  // The first run is writing once a child's capture file exists.
  REQUIRE(wait_until([&] { return !hidden_leftovers(out).empty(); }, 30));
  const Run other = run_locus(dir, cvt("101", {}));
  int ws = 0;
  const bool first_still_running = ::waitpid(first, &ws, WNOHANG) == 0;
  CHECK(other.status == 2);
  CHECK(has(other.err, out));
  CHECK(has(other.err, "cvt --sites 100 --iters 40"));
  CHECK(has(other.err, "cvt --sites 101 --iters 40"));
  CHECK(has(other.err, "Use another --out folder"));
  if (first_still_running) CHECK(has(other.err, "is being written by another run"));
  Run a;
  if (first_still_running) a = wait_locus(cap, first);
  else a.status = WIFEXITED(ws) ? WEXITSTATUS(ws) : -1;
  CHECK(a.status == 0);

  // Every report and the summary are the first run's.
  const json summary = json::parse(slurp(fs::path(out) / "summary.json"));
  CHECK(summary["pipeline_options"] == json::array({"--sites", "100", "--iters", "40"}));
  CHECK(summary["succeeded"] == 3);
  for (const json& item : summary["items"]) {
    const json report = json::parse(slurp(item["report"].get<std::string>()));
    CHECK(report["pipeline_options"] == summary["pipeline_options"]);
    CHECK(report["result"]["sites"] == 100);
  }

  // Finished: still refused, with the other message; same options still welcome.
  const Run later = run_locus(dir, cvt("101", {}));
  CHECK(later.status == 2);
  CHECK(has(later.err, "holds the results of another run"));
  CHECK(has(later.err, "remove " + out));
  const Run other_ext = run_locus(dir, cvt("100", {"--ext", "obj"}));
  CHECK(other_ext.status == 2);
  const Run same = run_locus(dir, cvt("100", {"--resume"}));
  CHECK(same.status == 0);
  CHECK(same.json()["resumed"] == 3);
  CHECK(hidden_leftovers(out).empty());
}

TEST_CASE("runner: summary.json does not list a report another run replaced") {
  if (!have_locus()) return;
  Scratch dir("runner-truth"), cap("runner-truth-x");
  // Two corpora with one file name in common: x.off is a sphere in one, a torus in the other.
  const fs::path c1 = dir.path / "c1", c2 = dir.path / "c2";
  fs::create_directories(c1);
  fs::create_directories(c2);
  locus::write_mesh((c1 / "x.off").string(), locus::make_icosphere(2));   // 162 vertices
  locus::write_mesh((c1 / "y.off").string(), locus::make_icosphere(5));   // 10242 vertices: a long item
  locus::write_mesh((c2 / "x.off").string(), locus::make_torus(20, 10));  // 200 vertices
  const std::string out = dir / "out";
  auto cvt = [&](const fs::path& in, const std::string& iters) {
    return std::vector<std::string>{"run", "cvt", in.string(), "--sites", "50", "--iters", iters, "--out", out,
                                    "--jobs", "1", "--threads", "1", "--json"};
  };
  // The first run reports x, then works on y while the second replaces x's report and output.
  const pid_t first = start_locus(cap, cvt(c1, "3"));
  REQUIRE(wait_until([&] { return fs::exists(fs::path(out) / "x.json"); }, 60));
  const Run second = run_locus(dir, cvt(c2 / "x.off", "3"));
  REQUIRE(second.status == 0);
  int ws = 0;
  const bool first_outlived_second = ::waitpid(first, &ws, WNOHANG) == 0;
  if (first_outlived_second) {
    const Run r = wait_locus(cap, first);
    const json s = json::parse(slurp(fs::path(out) / "summary.json"));
    REQUIRE(s["items"].size() == 2);
    const json& x = s["items"][0];
    CHECK(x["input"] == (c1 / "x.off").string());
    // x.json now holds the torus: the first run's summary must not claim it.
    CHECK(json::parse(slurp(fs::path(out) / "x.json"))["input"] == (c2 / "x.off").string());
    CHECK(x["report"].is_null());
    CHECK(x["output"].is_null());
    CHECK(x["status"] == "overwritten");
    CHECK(has(x["error"].get<std::string>(), "another run"));
    CHECK(s["items"][1]["status"] == "ok");
    CHECK(r.status == 3);
  } else {
    MESSAGE("the first run ended before the second: nothing to check");
    FAIL_CHECK("the long item ended before the second run: make it longer");
  }
}

TEST_CASE("runner: a run whose every input failed does not claim the folder") {
  if (!have_locus()) return;
  Scratch dir("runner-typo");
  locus::write_mesh(dir / "s.off", locus::make_icosphere(2));
  const std::string out = dir / "out";
  // A typo in an option: every input refuses it, exit 2, and the folder stays free.
  CHECK(run_locus(dir, {"run", "cvt", dir / "s.off", "--sites", "abc", "--out", out}).status == 2);
  CHECK_FALSE(fs::exists(fs::path(out) / ".locus-run.json"));
  const Run fixed = run_locus(dir, {"run", "cvt", dir / "s.off", "--sites", "20", "--iters", "2", "--out", out, "--json"});
  CHECK(fixed.status == 0);
  CHECK(fixed.json()["succeeded"] == 1);
  CHECK(fs::exists(fs::path(out) / ".locus-run.json"));
}
