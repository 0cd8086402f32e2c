// `locus run` killed with SIGKILL (tools/runner/child_process.cpp,
// out_folder_lock.cpp): its children die with it (no orphan keeps computing
// and writing into the folder), and the next run into the folder, here with
// --resume, removes the capture files and temporaries the killed run left,
// then finishes the work with the right results.
#include <doctest/doctest.h>

#include <signal.h>
#include <sys/wait.h>

#include <string>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/runner_support.hpp"

using namespace locus::test_cli;
using nlohmann::json;

TEST_CASE("runner: SIGKILL takes the children with it; --resume removes stale temporaries") {
  if (!have_locus()) return;
  Scratch dir("runner-kill"), cap("runner-kill-run");
  const fs::path in = dir.path / "in";
  fs::create_directories(in);
  const locus::Mesh big = locus::make_icosphere(5);     // 10242 vertices: a long item
  const locus::Mesh small = locus::make_torus(30, 15);  // 450 vertices
  locus::write_mesh((in / "a_big.off").string(), big);
  locus::write_mesh((in / "b_small.off").string(), small);
  const std::string out = dir / "out";
  const std::vector<std::string> args = {"run", "cvt", in.string(), "--sites", "300", "--iters", "60", "--out", out,
                                         "--jobs", "2", "--threads", "2", "--json"};
  const pid_t runner = start_locus(cap, args);
  // Wait until the long item's child runs.
  REQUIRE(wait_until([&] { return !children_of(runner).empty(); }, 30));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const std::vector<pid_t> kids = children_of(runner);
  REQUIRE(!kids.empty());
  ::kill(runner, SIGKILL);
  int ws = 0;
  ::waitpid(runner, &ws, 0);
  for (pid_t kid : kids) CHECK_MESSAGE(wait_until([&] { return process_gone(kid); }, 2), "child " << kid << " outlived");
  // What the killed run left: at least the long item's capture files.
  CHECK(!hidden_leftovers(out).empty());

  const Run again = run_locus(dir, [&] {
    auto a = args;
    a.push_back("--resume");
    return a;
  }());
  REQUIRE(again.status == 0);
  CHECK(hidden_leftovers(out).empty());
  const json s = again.json();
  CHECK(s["succeeded"] == 2);
  const json a = json::parse(slurp(fs::path(out) / "a_big.json"));
  CHECK(a["status"] == "ok");
  CHECK(a["result"]["n"] == big.num_vertices());
  CHECK(a["result"]["sites"] == 300);
  const locus::Mesh remesh = locus::read_mesh((fs::path(out) / "a_big.ply").string());
  CHECK(remesh.num_vertices() == a["result"]["remesh"]["vertices"].get<int32_t>());
  CHECK(remesh.num_faces() == 2 * remesh.num_vertices() - 4);  // closed genus 0, like the sphere
  const json b = json::parse(slurp(fs::path(out) / "b_small.json"));
  CHECK(b["result"]["n"] == small.num_vertices());
}
