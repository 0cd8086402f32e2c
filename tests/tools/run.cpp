// `locus run` (tools/runner/) as users run it: a folder with two good
// meshes, one garbage mesh file and one non-mesh file; the garbage is reported
// and skipped, the good ones produce their output and report, the summary
// counts are right and the exit status says an input failed (3). Ctrl-C
// (SIGINT to the runner) stops running items, keeps the summary, exits 5.
// Bad usage exits 2.
#include <doctest/doctest.h>

#include <signal.h>

#include <chrono>
#include <string>
#include <thread>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

TEST_CASE("run: cvt over a folder with a garbage file reports it, processes the rest, exit 3") {
  if (!have_locus()) return;
  Scratch dir("run");
  const fs::path in = dir.path / "in";
  fs::create_directories(in);
  const locus::Mesh sphere = locus::make_icosphere(3);  // 642 vertices
  const locus::Mesh torus = locus::make_torus(40, 20);  // 800 vertices
  locus::write_mesh((in / "a_sphere.off").string(), sphere);
  locus::write_mesh((in / "b_torus.obj").string(), torus);
  std::ofstream(in / "c_garbage.ply") << "ply\nformat ascii 1.0\nelement vertex lots\nend_header\n";
  std::ofstream(in / "notes.txt") << "not a mesh\n";
  const std::string out = dir / "out";

  const Run r = run_locus(dir, {"run", "cvt", in.string(), "--sites", "200", "--iters", "20", "--out", out, "--json",
                                "--jobs", "2", "--threads", "2"});
  CHECK(r.status == 3);
  const auto s = r.json();
  CHECK(s == nlohmann::json::parse(slurp(fs::path(out) / "summary.json")));
  CHECK(s["pipeline"] == "cvt");
  CHECK(s["inputs"] == 3);
  CHECK(s["succeeded"] == 2);
  CHECK(s["failed"] == 1);
  CHECK(s["ignored_files"] == 1);
  CHECK(s["threads_per_item"] == 1);
  REQUIRE(s["items"].size() == 3);
  // Sorted by name: sphere, torus, garbage.
  CHECK(s["items"][0]["status"] == "ok");
  CHECK(s["items"][1]["status"] == "ok");
  CHECK(s["items"][2]["status"] == "failed");
  CHECK(s["items"][2]["exit_status"] == 3);
  CHECK(s["items"][2]["error"].get<std::string>().find("c_garbage.ply") != std::string::npos);

  // Per-input reports hold the pipeline's own JSON; the outputs are the remeshes.
  const auto a = nlohmann::json::parse(slurp(fs::path(out) / "a_sphere.json"));
  CHECK(a["status"] == "ok");
  CHECK(a["result"]["command"] == "cvt");
  CHECK(a["result"]["n"] == sphere.num_vertices());
  CHECK(a["result"]["sites"] == 200);
  const auto b = nlohmann::json::parse(slurp(fs::path(out) / "b_torus.json"));
  CHECK(b["result"]["n"] == torus.num_vertices());
  const locus::Mesh back = locus::read_mesh((fs::path(out) / "a_sphere.ply").string());
  CHECK(back.num_vertices() == a["result"]["remesh"]["vertices"].get<int32_t>());
  CHECK(back.num_vertices() >= 190);  // 200 sites, a few empty cells at most, plus added ones
  CHECK(back.num_faces() == 2 * back.num_vertices() - 4);  // closed genus 0, like the sphere
  CHECK(fs::exists(fs::path(out) / "b_torus.ply"));
  CHECK_FALSE(fs::exists(fs::path(out) / "c_garbage.ply"));
  const auto c = nlohmann::json::parse(slurp(fs::path(out) / "c_garbage.json"));
  CHECK(c["status"] == "failed");
  CHECK(c["result"].is_null());
  CHECK(c["stderr"].get<std::string>().find("error") != std::string::npos);
  // No scratch files left behind (the hidden files are the folder's lock and options stamp).
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    CHECK((name[0] != '.' || name == ".locus-run.lock" || name == ".locus-run.json"));
  }

  // Everything readable: exit 0. A missing input: reported, exit 3.
  const std::string info_out = dir / "info";
  CHECK(run_locus(dir, {"run", "info", (in / "a_sphere.off").string(), (in / "b_torus.obj").string(), "--out",
                        info_out})
            .status == 0);
  const Run missing = run_locus(dir, {"run", "info", (in / "nope.off").string(), "--out", info_out, "--json"});
  CHECK(missing.status == 3);
  CHECK(missing.json()["failed"] == 1);
}

TEST_CASE("run: bad usage exits 2") {
  if (!have_locus()) return;
  Scratch dir("run-usage");
  locus::write_mesh(dir / "s.off", locus::make_icosphere(2));
  CHECK(run_locus(dir, {"run", "nosuchpipeline", dir / "s.off", "--out", dir / "o"}).status == 2);
  CHECK(run_locus(dir, {"run", "info", dir / "s.off"}).status == 2);                             // no --out
  CHECK(run_locus(dir, {"run", "info", "--out", dir / "o"}).status == 2);                        // no input
  CHECK(run_locus(dir, {"run", "info", dir / "s.off", "-o", "x.ply", "--out", dir / "o"}).status == 2);
  // Options every input refuses: the pipeline's bad usage, exit 2.
  const Run r = run_locus(dir, {"run", "cvt", dir / "s.off", "--sites", "abc", "--out", dir / "o", "--json"});
  CHECK(r.status == 2);
  CHECK(r.json()["items"][0]["exit_status"] == 2);
}

TEST_CASE("run: SIGINT stops running items, keeps the summary, exit 5") {
  if (!have_locus()) return;
  Scratch dir("run-cancel");
  const fs::path in = dir.path / "in";
  fs::create_directories(in);
  const locus::Mesh big = locus::make_icosphere(5);  // 10242 vertices: long CVT runs
  for (const char* name : {"m1.off", "m2.off", "m3.off", "m4.off"}) locus::write_mesh((in / name).string(), big);
  const std::string out = dir / "out";
  const pid_t pid = start_locus(dir, {"run", "cvt", in.string(), "--sites", "500", "--iters", "100000", "--solver",
                                      "full", "--out", out, "--jobs", "2", "--threads", "2", "--json"});
  // Wait until both children run (their scratch files exist), then interrupt.
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20)) {
    int started = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(out, ec))
      if (e.path().extension() == ".stderr") ++started;
    if (started == 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto t1 = std::chrono::steady_clock::now();
  ::kill(pid, SIGINT);
  const Run r = wait_locus(dir, pid);
  const double stop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  CHECK(r.status == 5);
  CHECK(stop_s < 12);  // children stop at their next cancellation check (SIGKILL after 10 s at the latest)
  REQUIRE(fs::exists(fs::path(out) / "summary.json"));
  const auto s = r.json();
  CHECK(s["stopped"] == "cancelled");
  CHECK(s["inputs"] == 4);
  CHECK(s["cancelled"] == 2);
  CHECK(s["not_run"] == 2);
  CHECK(s["items"][3]["status"] == "not_run");
  CHECK(fs::exists(fs::path(out) / "m1.json"));  // the interrupted items have reports
}
