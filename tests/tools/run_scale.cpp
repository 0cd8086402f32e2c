// `locus run` at scale:
// --recursive with the ignored files named, --shard K/N merged by --merge equal
// to the unsharded run, --resume skipping finished items, and two runs into one
// folder leaving every report whole and right.
#include <doctest/doctest.h>

#include <set>
#include <string>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;
using nlohmann::json;

namespace {

// A corpus with a subfolder and a non-mesh file.
fs::path make_corpus(const Scratch& dir) {
  const fs::path in = dir.path / "corpus";
  fs::create_directories(in / "sub");
  locus::write_mesh((in / "a_sphere.off").string(), locus::make_icosphere(2));
  locus::write_mesh((in / "b_torus.obj").string(), locus::make_torus(20, 10));
  locus::write_mesh((in / "sub" / "c_sphere.ply").string(), locus::make_icosphere(3));
  locus::write_mesh((in / "sub" / "d_torus.off").string(), locus::make_torus(24, 12));
  std::ofstream(in / "sub" / "notes.txt") << "not a mesh\n";
  return in;
}

// The summary's items without what differs between runs of the same work
// (timings, and the output folder in the paths).
json comparable_items(const json& summary, const std::string& out) {
  json items = summary["items"];
  for (json& it : items) {
    it.erase("seconds");
    for (const char* key : {"report", "output"})
      if (it[key].is_string()) {
        std::string p = it[key].get<std::string>();
        if (p.rfind(out, 0) == 0) p = p.substr(out.size());
        it[key] = p;
      }
  }
  return items;
}

}  // namespace

TEST_CASE("run: --recursive, --shard K/N merged equals the unsharded run, --resume skips finished items") {
  if (!have_locus()) return;
  Scratch dir("runscale");
  const fs::path in = make_corpus(dir);
  const std::vector<std::string> cvt = {"--sites", "20", "--iters", "3", "--threads", "2"};
  auto args = [&](std::vector<std::string> head, const std::string& out, std::vector<std::string> tail) {
    head.insert(head.end(), cvt.begin(), cvt.end());
    head.insert(head.end(), {"--out", out, "--json"});
    head.insert(head.end(), tail.begin(), tail.end());
    return head;
  };
  const std::string whole = dir / "whole", sharded = dir / "sharded";
  const Run all = run_locus(dir, args({"run", "cvt", in.string(), "--recursive"}, whole, {}));
  REQUIRE(all.status == 0);
  const json s = all.json();
  CHECK(s["inputs"] == 4);
  CHECK(s["ignored"] == json::array({(in / "sub" / "notes.txt").string()}));
  // Without --recursive the subfolder is not entered (and is not an ignored file).
  const Run flat = run_locus(dir, {"run", "info", in.string(), "--out", dir / "flat", "--json"});
  CHECK(flat.json()["inputs"] == 2);
  CHECK(flat.json()["ignored"].empty());

  const Run s1 = run_locus(dir, args({"run", "cvt", in.string(), "--recursive"}, sharded, {"--shard", "1/2"}));
  const Run s2 = run_locus(dir, args({"run", "cvt", in.string(), "--recursive"}, sharded, {"--shard", "2/2"}));
  REQUIRE(s1.status == 0);
  REQUIRE(s2.status == 0);
  CHECK(s1.json()["inputs"] == 2);
  CHECK(s2.json()["inputs"] == 2);
  CHECK(fs::exists(fs::path(sharded) / "summary-1-of-2.json"));
  const Run merged = run_locus(dir, {"run", "--merge", sharded, "--json"});
  REQUIRE(merged.status == 0);
  const json m = merged.json();
  CHECK(m == json::parse(slurp(fs::path(sharded) / "summary.json")));
  CHECK(comparable_items(m, sharded) == comparable_items(s, whole));
  for (const char* key : {"inputs", "succeeded", "failed", "ignored", "pipeline", "pipeline_options", "exit_status"})
    CHECK(m[key] == s[key]);
  // Each shard's outputs equal the unsharded run's (same seed, same input).
  CHECK(slurp(fs::path(sharded) / "c_sphere.ply") == slurp(fs::path(whole) / "c_sphere.ply"));
  // A missing shard is refused, not silently merged.
  fs::remove(fs::path(sharded) / "summary-2-of-2.json");
  const Run partial = run_locus(dir, {"run", "--merge", sharded});
  CHECK(partial.status == 3);
  CHECK(partial.err.find("shard 2/2 is missing") != std::string::npos);

  // --resume: every report says ok for this command line, nothing runs again;
  // other options are not a match.
  const Run again = run_locus(dir, args({"run", "cvt", in.string(), "--recursive"}, whole, {"--resume"}));
  REQUIRE(again.status == 0);
  CHECK(again.json()["resumed"] == 4);
  fs::remove(fs::path(whole) / "b_torus.json");
  const Run redo = run_locus(dir, args({"run", "cvt", in.string(), "--recursive"}, whole, {"--resume"}));
  CHECK(redo.json()["resumed"] == 3);
  CHECK(fs::exists(fs::path(whole) / "b_torus.json"));
  const Run other = run_locus(dir, {"run", "cvt", in.string(), "--recursive", "--sites", "21", "--iters", "3", "--out",
                                    whole, "--json", "--resume"});
  CHECK(other.status == 2);  // the folder holds the results of other options: refused, nothing resumed
  CHECK(other.out.empty());
}

TEST_CASE("run: two runs into one folder keep every report whole") {
  if (!have_locus()) return;
  Scratch dir("runtwice"), cap1("runtwice1"), cap2("runtwice2");
  const fs::path in = make_corpus(dir);
  const std::string out = dir / "out";
  const std::vector<std::string> a = {"run", "cvt", in.string(), "--recursive", "--sites", "20", "--iters", "3",
                                      "--out", out, "--jobs", "2", "--json"};
  const pid_t p1 = start_locus(cap1, a);
  const pid_t p2 = start_locus(cap2, a);
  const Run r1 = wait_locus(cap1, p1), r2 = wait_locus(cap2, p2);
  CHECK(r1.status == 0);
  CHECK(r2.status == 0);
  const json summary = json::parse(slurp(fs::path(out) / "summary.json"));
  CHECK(summary["succeeded"] == 4);
  for (const json& item : summary["items"]) {
    const json report = json::parse(slurp(item["report"].get<std::string>()));
    CHECK(report["status"] == "ok");
    CHECK(report["result"].is_object());
    CHECK(report["result"]["command"] == "cvt");
  }
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    CHECK((name[0] != '.' || name == ".locus-run.lock" || name == ".locus-run.json"));
  }
}
