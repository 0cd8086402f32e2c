// Preview camera (kernels/render/preview_camera.hpp) and what the picture says
// (legend, markers): checked against geometry that fixes the answer — an
// ellipsoid whose axes are known, the same mesh turned from y-up to z-up
// (the picture must not change), a plane seen straight on.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/render/bitmap_font.hpp"
#include "locus/kernels/render/colour_map.hpp"
#include "locus/kernels/render/preview_annotations.hpp"
#include "locus/kernels/render/preview_camera.hpp"
#include "locus/kernels/render/rasterize.hpp"

namespace {

// An ellipsoid with semi-axes (a, b, c) along x, y, z, with a bump at +x+y
// so that no mirror symmetry hides a wrong sign.
locus::Mesh ellipsoid(double a, double b, double c) {
  locus::Mesh m = locus::make_icosphere(3);
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double bump = 1 + 0.3 * std::exp(-8 * ((m.x[v] - 0.6) * (m.x[v] - 0.6) + (m.y[v] - 0.6) * (m.y[v] - 0.6)));
    m.x[v] *= a * bump;
    m.y[v] *= b * bump;
    m.z[v] *= c * bump;
  }
  return m;
}

// y-up -> z-up: (x, y, z) -> (x, -z, y), a rotation by 90 degrees about x.
locus::Mesh turned_z_up(locus::Mesh m) {
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double y = m.y[v], z = m.z[v];
    m.y[v] = -z;
    m.z[v] = y;
  }
  return m;
}

double dot(const locus::Vec3d& a, const locus::Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

TEST_CASE("symmetric_eigen3: eigenpairs of a rotated diagonal matrix") {
  // A = R diag(5, 2, -1) R^T with R a rotation; eigenvalues descending, A v = lambda v.
  const double c = std::cos(0.7), s = std::sin(0.7);
  const std::array<locus::Vec3d, 3> R{locus::Vec3d{c, -s, 0}, locus::Vec3d{s * 0.6, c * 0.6, -0.8},
                                      locus::Vec3d{s * 0.8, c * 0.8, 0.6}};
  const double d[3] = {5, 2, -1};
  std::array<locus::Vec3d, 3> A{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) A[i][j] += R[i][k] * d[k] * R[j][k];
  const locus::SymmetricEigen3 e = locus::symmetric_eigen3(A);
  for (int k = 0; k < 3; ++k) {
    CHECK(e.values[k] == doctest::Approx(d[k]).epsilon(1e-12));
    for (int i = 0; i < 3; ++i) {
      const double av = A[i][0] * e.vectors[k][0] + A[i][1] * e.vectors[k][1] + A[i][2] * e.vectors[k][2];
      CHECK(av == doctest::Approx(e.values[k] * e.vectors[k][i]).epsilon(1e-10).scale(1));
    }
  }
}

TEST_CASE("preview camera: a standing and a lying figure are upright, y-up or z-up") {
  // Standing (tallest along y): up is +y; lying (longest along x, height y): up is still +y.
  for (const auto& abc : {std::array<double, 3>{1, 3, 0.5}, std::array<double, 3>{3, 1, 0.5}}) {
    const double a = abc[0], b = abc[1], c = abc[2];  // not bindings: CAPTURE takes them in a lambda
    CAPTURE(a);
    const locus::Mesh y_up = ellipsoid(a, b, c);
    const locus::PreviewCamera cy = locus::principal_axes_camera(y_up);
    CHECK(cy.up[1] > 0.9);
    CHECK_FALSE(cy.one_sided);
    // Looking along the thinnest axis (z), from -z, turned 30 and raised 20 degrees.
    CHECK(cy.back[2] == doctest::Approx(-std::cos(M_PI / 6) * std::cos(M_PI / 9)).epsilon(1e-3));
    const locus::PreviewCamera cz = locus::principal_axes_camera(turned_z_up(y_up));
    CHECK(cz.up[2] > 0.9);
    // The same camera relative to the mesh: turning the mesh turns the camera.
    CHECK(cz.back[0] == doctest::Approx(cy.back[0]).epsilon(1e-9));
    CHECK(cz.back[1] == doctest::Approx(-cy.back[2]).epsilon(1e-9));
    CHECK(cz.back[2] == doctest::Approx(cy.back[1]).epsilon(1e-9));
    // Orthonormal, right-handed (right x up = back).
    CHECK(dot(cz.right, cz.up) == doctest::Approx(0).scale(1));
    CHECK(dot(cz.up, cz.back) == doctest::Approx(0).scale(1));
    const locus::Vec3d rxu{cz.right[1] * cz.up[2] - cz.right[2] * cz.up[1], cz.right[2] * cz.up[0] - cz.right[0] * cz.up[2],
                           cz.right[0] * cz.up[1] - cz.right[1] * cz.up[0]};
    CHECK(dot(rxu, cz.back) == doctest::Approx(1));
  }
}

TEST_CASE("preview camera: the picture of a z-up mesh equals the picture of the same mesh y-up") {
  const locus::Mesh y_up = ellipsoid(1, 3, 0.5);
  const locus::Mesh z_up = turned_z_up(y_up);
  std::vector<double> values(static_cast<size_t>(y_up.num_vertices()));
  for (int32_t v = 0; v < y_up.num_vertices(); ++v) values[v] = y_up.x[v] + 2 * y_up.y[v];  // same per vertex
  locus::RasterOptions ro;
  ro.width = 200;
  ro.height = 200;
  const locus::RasterImage a = locus::rasterize_mesh(y_up, values, ro);
  const locus::RasterImage b = locus::rasterize_mesh(z_up, values, ro);
  size_t differ = 0, covered = 0;
  for (size_t p = 0; p < a.rgb.size(); p += 3) {
    covered += a.rgb[p] != 242 || a.rgb[p + 1] != 242;
    differ += std::abs(a.rgb[p] - b.rgb[p]) + std::abs(a.rgb[p + 1] - b.rgb[p + 1]) + std::abs(a.rgb[p + 2] - b.rgb[p + 2]) > 6;
  }
  CHECK(covered > 5000);
  CHECK(differ < covered / 200);  // rounding of the turned coordinates only
}

TEST_CASE("preview camera: a terrain is seen from above, its bumps pointing up on screen") {
  // A height field over the unit square, z-up; the normals agree: one-sided, up = +z.
  locus::Mesh m = locus::make_grid(20);
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    m.z[v] = 0.3 * std::exp(-20 * ((m.x[v] - 0.5) * (m.x[v] - 0.5) + (m.y[v] - 0.5) * (m.y[v] - 0.5)));
  const locus::PreviewCamera cam = locus::principal_axes_camera(m);
  CHECK(cam.one_sided);
  CHECK(cam.up[2] > 0.6);     // z projects upwards on the screen
  CHECK(cam.back[2] > 0.6);   // the camera is above (40 degrees up from level)
  // --view replaces the side: from straight above.
  const locus::PreviewCamera top = locus::principal_axes_camera(m, locus::Vec3d{0, 0, 2});
  CHECK(top.back[2] == doctest::Approx(1));
  CHECK(std::abs(top.up[2]) < 1e-12);
}

TEST_CASE("preview legend and markers: the strip, the colour bar's ends, a marker at a known point") {
  // A flat square seen straight on (--view 0,0,1): its centre is the picture's centre.
  const locus::Mesh m = locus::make_grid(10);
  std::vector<double> values(static_cast<size_t>(m.num_vertices()));
  for (int32_t v = 0; v < m.num_vertices(); ++v) values[v] = 10 * m.x[v];
  locus::RasterOptions ro;
  ro.width = 400;
  ro.height = 400;
  ro.bands = 0;
  ro.view = locus::Vec3d{0, 0, 1};
  const locus::RasterImage plain = locus::rasterize_mesh(m, values, ro);
  ro.title = "distance";
  ro.markers = {{0.5, 0.5, 0.0}};
  ro.marker_label = "source";
  const locus::RasterImage img = locus::rasterize_mesh(m, values, ro);
  const int lh = locus::legend_height(400, 400, ro.title);
  REQUIRE(lh > 30);
  REQUIRE(lh < 200);
  const int ph = 400 - lh;
  auto px = [&](const locus::RasterImage& im, int x, int y) { return &im.rgb[3 * (static_cast<size_t>(y) * im.width + x)]; };
  // The marker: white at the projected centre of the picture area.
  const uint8_t* c = px(img, 200, ph / 2);
  CHECK((c[0] == 255 && c[1] == 255 && c[2] == 255));
  // Without a legend the surface covers that pixel in colour.
  const uint8_t* p = px(plain, 200, 200);
  CHECK_FALSE((p[0] == p[1] && p[1] == p[2]));
  // The legend strip is white with dark text pixels in its first row of text.
  size_t dark = 0;
  for (int y = ph; y < ph + 9; ++y)
    for (int x = 0; x < 400; ++x) dark += px(img, x, y)[0] < 80;
  CHECK(dark > 20);
  // The colour bar runs from the map's first colour to its last (smooth: bands = 0).
  int bar_y = -1;
  for (int y = ph; y < 400 && bar_y < 0; ++y)
    if (px(img, 200, y)[0] != 255 || px(img, 200, y)[2] != 255) bar_y = y > ph + 12 ? y : -1;
  REQUIRE(bar_y > 0);
  const locus::Rgb lo = locus::scalar_colour(0.0, 0), hi = locus::scalar_colour(1.0, 0);
  const uint8_t* l = px(img, 13, bar_y + 4);
  const uint8_t* h = px(img, 400 - 14, bar_y + 4);
  for (int d = 0; d < 3; ++d) {
    CHECK(std::abs(l[d] - lo[d] * 255) < 8);
    CHECK(std::abs(h[d] - hi[d] * 255) < 8);
  }
}

TEST_CASE("bitmap font: every printable ASCII letter and digit has its own glyph") {
  locus::RasterImage box{8, 12, std::vector<uint8_t>(8 * 12 * 3, 255)};
  locus::draw_text(box, 1, 1, "\x01", 1, {0, 0, 0});
  for (char ch : std::string("0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ.,-+=()/:_^%<>[]*|#' ")) {
    CAPTURE(ch);
    locus::RasterImage g{8, 12, std::vector<uint8_t>(8 * 12 * 3, 255)};
    locus::draw_text(g, 1, 1, std::string(1, ch), 1, {0, 0, 0});
    CHECK(g.rgb != box.rgb);  // not the unknown-character box
  }
  CHECK(locus::text_width("abc", 2) == (3 * locus::kGlyphAdvance - 1) * 2);
  // Clipped at the image's edges, no write outside.
  locus::RasterImage tiny{3, 3, std::vector<uint8_t>(27, 255)};
  locus::draw_text(tiny, -4, -4, "WWWW", 3, {0, 0, 0});
  CHECK(tiny.rgb.size() == 27u);
}
