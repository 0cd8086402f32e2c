// `--save F.locus` / `--load F.locus` as users run them (tools/cli,
// io/factor_cache): a loaded factor gives bit-identical results to the one
// that was saved (heat values, heat kernel signature at two t, the factor
// command's residual), and the CLI refuses, with exit status 3 and a message
// naming the file, a cache made for another mesh, another t, a truncated or a
// corrupted file; --save with --load is bad usage (2).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

namespace {

// An icosphere (2562 vertices) and the same sphere with one vertex moved.
struct Meshes {
  std::string sphere, moved;
  explicit Meshes(const Scratch& dir) {
    locus::Mesh m = locus::make_icosphere(4);
    sphere = dir / "sphere.off";
    locus::write_mesh(sphere, m);
    m.x[7] += 0.01;  // (icosahedron corners have zero coordinates: add, do not scale)
    moved = dir / "moved.off";
    locus::write_mesh(moved, m);
  }
};

void corrupt_byte(const std::string& path, size_t from_end) {
  std::string data = slurp(path);
  REQUIRE(data.size() > from_end);
  data[data.size() - from_end] = static_cast<char>(data[data.size() - from_end] ^ 0x5a);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << data;
}

}  // namespace

TEST_CASE("factor cache CLI: a loaded factor gives bit-identical results") {
  if (!have_locus()) return;
  Scratch dir("fcache");
  const Meshes m(dir);
  const std::string cache = dir / "heat.locus";
  const std::vector<std::string> heat = {"heat", m.sphere, "--source", "0,10", "--target", "5,300,2000", "--json"};
  auto with = [](std::vector<std::string> a, std::initializer_list<std::string> more) {
    a.insert(a.end(), more);
    return a;
  };
  const Run saved = run_locus(dir, with(heat, {"--save", cache}));
  REQUIRE(saved.status == 0);
  REQUIRE(fs::exists(cache));
  const Run loaded = run_locus(dir, with(heat, {"--load", cache}));
  REQUIRE(loaded.status == 0);
  const auto a = saved.json(), b = loaded.json();
  CHECK(a["factor_cache"]["saved"] == cache);
  CHECK(b["factor_cache"]["loaded"] == cache);
  CHECK(b["factor_s"].get<double>() == 0.0);  // nothing was factored
  // JSON doubles print with 17 significant digits: equal text = equal bits.
  REQUIRE(a["values"].size() == 3);
  for (size_t k = 0; k < 3; ++k) {
    CHECK(a["values"][k].get<double>() > 0);
    CHECK(a["values"][k].get<double>() == b["values"][k].get<double>());
  }

  // The factor command reads the same file (heat at t = h^2 is its default operator).
  const Run f1 = run_locus(dir, {"factor", m.sphere, "--json"});
  const Run f2 = run_locus(dir, {"factor", m.sphere, "--json", "--load", cache});
  REQUIRE(f1.status == 0);
  REQUIRE(f2.status == 0);
  CHECK(f1.json()["residual"].get<double>() == f2.json()["residual"].get<double>());
  CHECK(f2.json()["residual"].get<double>() < 1e-12);

  // Several factors in one file: the heat kernel signature at two t.
  const std::string hks_cache = dir / "hks.locus";
  const std::vector<std::string> hks = {"hks", m.sphere, "--ts", "1h2,4h2", "--vertices", "3,9,1000", "--json"};
  const Run h1 = run_locus(dir, with(hks, {"--save", hks_cache}));
  const Run h2 = run_locus(dir, with(hks, {"--load", hks_cache}));
  REQUIRE(h1.status == 0);
  REQUIRE(h2.status == 0);
  CHECK(h1.json()["hks"] == h2.json()["hks"]);
  CHECK(h1.json()["hks"][0][0].get<double>() != h1.json()["hks"][0][1].get<double>());

  // Wrong t: refused.
  const Run wrong_t = run_locus(dir, {"hks", m.sphere, "--ts", "1h2,5h2", "--vertices", "3", "--load", hks_cache});
  CHECK(wrong_t.status == 3);
  CHECK(wrong_t.err.find(hks_cache) != std::string::npos);
  // A cache of two factors where the command needs one: refused.
  CHECK(run_locus(dir, with(heat, {"--load", hks_cache})).status == 3);
}

TEST_CASE("factor cache CLI: another mesh, truncated, corrupted, missing files exit 3") {
  if (!have_locus()) return;
  Scratch dir("fcache-bad");
  const Meshes m(dir);
  const std::string cache = dir / "f.locus";
  REQUIRE(run_locus(dir, {"factor", m.sphere, "--save", cache}).status == 0);
  const std::string good = slurp(cache);

  const Run other = run_locus(dir, {"factor", m.moved, "--load", cache});
  CHECK(other.status == 3);
  CHECK(other.err.find("another mesh") != std::string::npos);
  // The same file after --subdivide is another mesh too.
  CHECK(run_locus(dir, {"factor", m.sphere, "--subdivide", "1", "--load", cache}).status == 3);
  // Another operator.
  const Run op = run_locus(dir, {"factor", m.sphere, "--operator", "laplacian", "--load", cache});
  CHECK(op.status == 3);
  CHECK(op.err.find("laplacian") != std::string::npos);

  for (size_t keep : {size_t(0), size_t(20), good.size() / 2, good.size() - 8}) {
    CAPTURE(keep);
    const std::string cut = dir / "cut.locus";
    std::ofstream(cut, std::ios::binary | std::ios::trunc) << good.substr(0, keep);
    const Run r = run_locus(dir, {"factor", m.sphere, "--load", cut});
    CHECK(r.status == 3);
    CHECK(r.err.find(cut) != std::string::npos);
  }
  // A flipped byte in the last section (factor values): checksum.
  const std::string broken = dir / "broken.locus";
  std::ofstream(broken, std::ios::binary | std::ios::trunc) << good;
  corrupt_byte(broken, 100);
  const Run c = run_locus(dir, {"factor", m.sphere, "--load", broken});
  CHECK(c.status == 3);
  CHECK(c.err.find("corrupted") != std::string::npos);
  // Another format version (byte 8 of the header).
  std::string v = good;
  v[8] = static_cast<char>(v[8] + 1);
  std::ofstream(broken, std::ios::binary | std::ios::trunc) << v;
  const Run ver = run_locus(dir, {"factor", m.sphere, "--load", broken});
  CHECK(ver.status == 3);
  CHECK(ver.err.find("format") != std::string::npos);

  CHECK(run_locus(dir, {"factor", m.sphere, "--load", dir / "missing.locus"}).status == 3);
  CHECK(run_locus(dir, {"factor", m.sphere, "--load", cache, "--save", dir / "x.locus"}).status == 2);
  CHECK(run_locus(dir, {"factor", m.sphere, "--max-memory", "lots"}).status == 2);
  CHECK(run_locus(dir, {"factor", m.sphere, "--max-memory", "1.5G"}).status == 0);
}
