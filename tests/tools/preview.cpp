// Previews (--preview out.png; kernels/rasterize, io/write_png): the PNG a
// command writes decodes (stb_image, the library that wrote it) to 800 x 800
// RGB with many colours; the kernel's picture of a known scene has the mesh
// where the camera must put it and the background elsewhere; bad sizes and
// names are refused.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>

#include "locus/io/write_png.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/render/rasterize.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

using namespace locus::test_cli;

namespace {

struct Decoded {
  int w = 0, h = 0, channels = 0;
  std::set<uint32_t> colours;
};

Decoded decode(const std::string& path) {
  Decoded d;
  unsigned char* px = stbi_load(path.c_str(), &d.w, &d.h, &d.channels, 3);
  REQUIRE(px != nullptr);
  for (int i = 0; i < d.w * d.h; ++i)
    d.colours.insert(uint32_t(px[3 * i]) << 16 | uint32_t(px[3 * i + 1]) << 8 | px[3 * i + 2]);
  stbi_image_free(px);
  return d;
}

std::string read_file(const std::string& path) { return slurp(path); }

}  // namespace

TEST_CASE("preview: geodesic, logmap and adf write decodable, non-uniform PNGs") {
  if (!have_locus()) return;
  Scratch dir("preview");
  const std::string mesh = dir / "sphere.off";
  locus::write_mesh(mesh, locus::make_icosphere(4));
  struct Case {
    std::vector<std::string> args;
    size_t min_colours;
  };
  const std::vector<Case> cases = {
      {{"geodesic", mesh, "--source", "0", "--preview", dir / "geo.png"}, 200},
      {{"logmap", mesh, "--center", "0", "--fraction", "0.3", "--preview", dir / "log.png"}, 50},
      {{"adf", mesh, "--all", "--preview", dir / "adf.png"}, 50},
  };
  for (const Case& c : cases) {
    CAPTURE(c.args[0]);
    const Run r = run_locus(dir, c.args);
    REQUIRE(r.status == 0);
    const Decoded d = decode(c.args.back());
    CHECK(d.w == 800);
    CHECK(d.h == 800);
    CHECK(d.colours.size() >= c.min_colours);
  }
  CHECK(run_locus(dir, {"geodesic", mesh, "--source", "0", "--preview", dir / "geo.jpg"}).status == 2);
  CHECK(run_locus(dir, {"geodesic", mesh, "--source", "0", "--preview", dir / "v.png", "--view", "0,0"}).status == 2);
  CHECK(run_locus(dir, {"geodesic", mesh, "--source", "0", "--preview", dir / "v.png", "--view", "0,0,0"}).status == 2);
  CHECK(run_locus(dir, {"geodesic", mesh, "--source", "0", "--view", "0,0,1"}).status == 2);  // --view without --preview
  CHECK(run_locus(dir, {"geodesic", mesh, "--source", "0", "--preview", dir / "v.png", "--view", "1,0,0"}).status == 0);
  CHECK(run_locus(dir, {"adf", mesh, "--vertices", "1", "--preview", dir / "adf.png"}).status == 2);
}

TEST_CASE("rasterize: a square facing the camera lands in the middle, background around it") {
  // A flat square in the plane z = 0: seen by the fixed camera (yaw 210, pitch 20
  // degrees, orthographic, fitted to 90% of the image) it covers the center, not
  // the corners.
  locus::Mesh m = locus::make_grid(8);
  std::vector<double> values(static_cast<size_t>(m.num_vertices()));
  for (int32_t v = 0; v < m.num_vertices(); ++v) values[v] = m.x[v];
  locus::RasterOptions ro;
  ro.width = 120;
  ro.height = 100;
  const locus::RasterImage img = locus::rasterize_mesh(m, values, ro);
  REQUIRE(img.rgb.size() == 120u * 100u * 3u);
  auto px = [&](int x, int y) { return &img.rgb[3 * (static_cast<size_t>(y) * 120 + x)]; };
  CHECK(px(0, 0)[0] == 242);  // background
  CHECK(px(119, 99)[1] == 242);
  const uint8_t* c = px(60, 50);
  CHECK_FALSE((c[0] == 242 && c[1] == 242 && c[2] == 242));
  // Scalar colouring follows x: the two sides of the square differ in colour.
  std::set<uint32_t> row;
  for (int x = 0; x < 120; ++x) row.insert(uint32_t(px(x, 50)[0]) << 16 | uint32_t(px(x, 50)[1]) << 8 | px(x, 50)[2]);
  CHECK(row.size() > 10);
  // Labels (cvt cells): one flat colour per label, nearest corner; 4 quadrant labels give 4 hues (+ shading).
  for (int32_t v = 0; v < m.num_vertices(); ++v) values[v] = (m.x[v] < 0.5 ? 0 : 1) + (m.y[v] < 0.5 ? 0 : 2);
  ro.coloring = locus::Coloring::Labels;
  const locus::RasterImage lab = locus::rasterize_mesh(m, values, ro);
  std::set<uint32_t> hues;
  for (size_t p = 0; p < lab.rgb.size(); p += 3) {
    const uint8_t* q = &lab.rgb[p];
    if (q[0] == 242 && q[1] == 242 && q[2] == 242) continue;
    // Normalize out the (uniform, flat-plane) shading: compare colour ratios.
    const int mx = std::max({q[0], q[1], q[2]});
    hues.insert(uint32_t(q[0] * 8 / (mx + 1)) << 8 | uint32_t(q[1] * 8 / (mx + 1)) << 4 | uint32_t(q[2] * 8 / (mx + 1)));
  }
  CHECK(hues.size() >= 4);
  CHECK(hues.size() <= 6);  // a flat plane: no shading variation, only the label colours (plus edge rounding)
  // Wrong sizes are usage errors.
  CHECK_THROWS_AS(locus::rasterize_mesh(m, std::span<const double>(values.data(), 3), ro), locus::Error);
  ro.coloring = locus::Coloring::Checker;
  CHECK_THROWS_AS(locus::rasterize_mesh(m, values, ro), locus::Error);
  CHECK_THROWS_AS(locus::write_png("/nonexistent-dir/x.png", 2, 2, std::vector<uint8_t>(12, 0)), locus::Error);
  CHECK_THROWS_AS(locus::write_png("x.png", 2, 2, std::vector<uint8_t>(11, 0)), locus::Error);
}

TEST_CASE("preview: hks writes one image per t (or the one --preview-t names), and the JSON lists them") {
  if (!have_locus()) return;
  Scratch dir("preview_hks");
  const std::string mesh = dir / "sphere.off";
  locus::write_mesh(mesh, locus::make_icosphere(3));
  const Run r = run_locus(dir, {"hks", mesh, "--ts", "1h2,10h2,100h2", "--all", "--preview", dir / "h.png", "--json"});
  REQUIRE(r.status == 0);
  const auto j = r.json();
  REQUIRE(j["preview"].is_array());
  REQUIRE(j["preview"].size() == 3u);
  std::set<std::string> bytes;
  for (int t = 0; t < 3; ++t) {
    const std::string path = dir / ("h-t" + std::to_string(t) + ".png");
    CHECK(j["preview"][t] == path);
    const Decoded d = decode(path);
    CHECK(d.w == 800);
    bytes.insert(read_file(path));
  }
  CHECK(bytes.size() == 3u);  // three different pictures (the legends name their t at least)
  const Run one = run_locus(dir, {"hks", mesh, "--ts", "1h2,10h2,100h2", "--all", "--preview", dir / "one.png",
                                  "--preview-t", "2", "--json"});
  REQUIRE(one.status == 0);
  CHECK(one.json()["preview"] == dir / "one.png");
  CHECK(read_file(dir / "one.png") == read_file(dir / "h-t2.png"));
  CHECK(run_locus(dir, {"hks", mesh, "--ts", "1h2,10h2", "--all", "--preview", dir / "x.png", "--preview-t", "2"}).status == 2);
  CHECK(run_locus(dir, {"hks", mesh, "--ts", "1h2,10h2", "--all", "--preview-t", "1"}).status == 2);
}

TEST_CASE("preview: locus run --preview writes one image per item into --out") {
  if (!have_locus()) return;
  Scratch dir("preview_run");
  const std::string in = dir / "in";
  std::filesystem::create_directories(in);
  locus::write_mesh(in + "/a.off", locus::make_icosphere(2));
  locus::write_mesh(in + "/b.off", locus::make_icosphere(3));
  const Run r = run_locus(dir, {"run", "geodesic", in, "--source", "0", "--preview", "--out", dir / "out", "--json"});
  REQUIRE(r.status == 0);
  const auto j = r.json();
  for (const char* stem : {"a", "b"}) {
    const std::string png = dir / (std::string("out/") + stem + ".png");
    CHECK(decode(png).w == 800);
  }
  CHECK(read_file(dir / "out/a.png") != read_file(dir / "out/b.png"));
  for (const auto& item : j["items"]) CHECK(item["preview"].is_string());
  // A file name would make every item overwrite one image: refused.
  CHECK(run_locus(dir, {"run", "geodesic", in, "--source", "0", "--preview", dir / "x.png", "--out", dir / "out2"}).status == 2);
}
