// Legend and markers of previews (kernels/include/locus/kernels/render/preview_annotations.hpp).
#include "locus/kernels/render/preview_annotations.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "locus/core/format_significant.hpp"
#include "locus/kernels/render/bitmap_font.hpp"
#include "locus/kernels/render/colour_map.hpp"

namespace locus {

namespace {

constexpr std::array<uint8_t, 3> kInk{30, 30, 30};

void fill_rect(RasterImage& img, int x0, int y0, int x1, int y1, const Rgb& c) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, img.width), y1 = std::min(y1, img.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int d = 0; d < 3; ++d)
        img.rgb[3 * (static_cast<size_t>(y) * img.width + x) + d] =
            static_cast<uint8_t>(std::lround(std::clamp(c[d], 0.0, 1.0) * 255));
}

void frame_rect(RasterImage& img, int x0, int y0, int x1, int y1) {
  const Rgb ink{kInk[0] / 255.0, kInk[1] / 255.0, kInk[2] / 255.0};
  fill_rect(img, x0 - 1, y0 - 1, x1 + 1, y0, ink);
  fill_rect(img, x0 - 1, y1, x1 + 1, y1 + 1, ink);
  fill_rect(img, x0 - 1, y0, x0, y1, ink);
  fill_rect(img, x1, y0, x1 + 1, y1, ink);
}

// Text that does not fit in `room` pixels is cut with "...".
std::string fitted(std::string text, int room, int scale) {
  if (text_width(text, scale) <= room) return text;
  while (!text.empty() && text_width(text + "...", scale) > room) text.pop_back();
  return text + "...";
}

}  // namespace

int legend_text_scale(int width) { return std::max(1, width / 400); }

int legend_height(int width, int height, const std::string& title) {
  if (title.empty()) return 0;
  const int s = legend_text_scale(width);
  return std::min(height / 2, 3 * kGlyphHeight * s + 8 * s + 16 * s);
}

std::string legend_number(double v) { return format_significant(v, 4); }

void draw_marker(RasterImage& img, double x, double y, double r, bool hidden) {
  const double ring = std::max(1.5, 0.35 * r);
  const int x0 = static_cast<int>(std::floor(x - r - 1)), x1 = static_cast<int>(std::ceil(x + r + 1));
  const int y0 = static_cast<int>(std::floor(y - r - 1)), y1 = static_cast<int>(std::ceil(y + r + 1));
  for (int py = std::max(y0, 0); py <= std::min(y1, img.height - 1); ++py)
    for (int px = std::max(x0, 0); px <= std::min(x1, img.width - 1); ++px) {
      const double d = std::hypot(px + 0.5 - x, py + 0.5 - y);
      if (d > r) continue;
      uint8_t* p = &img.rgb[3 * (static_cast<size_t>(py) * img.width + px)];
      if (d > r - ring) {
        p[0] = 20, p[1] = 20, p[2] = 20;
      } else if (!hidden) {
        p[0] = 255, p[1] = 255, p[2] = 255;
      }
    }
}

void draw_legend(RasterImage& img, int top, const LegendContent& c) {
  if (c.title.empty() || top >= img.height) return;
  const int s = legend_text_scale(img.width);
  const int margin = 12 * s, line = kGlyphHeight * s + 4 * s;
  fill_rect(img, 0, top, img.width, img.height, {1, 1, 1});
  int y = top + 4 * s;
  // Line 1: title, with the marker symbol and its label at the right end.
  int title_room = img.width - 2 * margin;
  if (!c.marker_label.empty()) {
    const int w = text_width(c.marker_label, s) + 4 * kGlyphHeight * s / 3;
    title_room -= w + margin;
    const int mx = img.width - margin - text_width(c.marker_label, s);
    draw_marker(img, mx - kGlyphHeight * s * 0.75, y + kGlyphHeight * s * 0.4, kGlyphHeight * s * 0.45, false);
    draw_text(img, mx, y, c.marker_label, s, kInk);
  }
  draw_text(img, margin, y, fitted(c.title, title_room, s), s, kInk);
  y += line + 2 * s;
  // Line 2: the colour key; line 3: its numbers.
  const int swatch = kGlyphHeight * s;
  int right = img.width - margin;
  if (c.missing) {
    const std::string t = "no value";
    const int tx = right - text_width(t, s);
    fill_rect(img, tx - swatch - 4 * s, y, tx - 4 * s, y + swatch, kNoValueGrey);
    frame_rect(img, tx - swatch - 4 * s, y, tx - 4 * s, y + swatch);
    draw_text(img, tx, y, t, s, kInk);
    right = tx - swatch - 4 * s - margin;
  }
  if (c.coloring == Coloring::Scalar) {
    if (!(c.vmin <= c.vmax)) {
      draw_text(img, margin, y, "no finite value", s, kInk);
      return;
    }
    const int x0 = margin, x1 = std::max(x0 + 10, right);
    for (int x = x0; x < x1; ++x)
      fill_rect(img, x, y, x + 1, y + swatch, scalar_colour((x + 0.5 - x0) / (x1 - x0), c.bands));
    frame_rect(img, x0, y, x1, y + swatch);
    const int ty = y + swatch + 3 * s;
    const std::string lo = (c.clipped_low ? "<=" : "") + legend_number(c.vmin);
    const std::string hi = (c.clipped_high ? ">=" : "") + legend_number(c.vmax);
    const std::string mid = legend_number(0.5 * (c.vmin + c.vmax));
    draw_text(img, x0, ty, lo, s, kInk);
    draw_text(img, x1 - text_width(hi, s), ty, hi, s, kInk);
    const int mx = (x0 + x1 - text_width(mid, s)) / 2;
    if (mx > x0 + text_width(lo, s) + margin && mx + text_width(mid, s) + margin < x1 - text_width(hi, s))
      draw_text(img, mx, ty, mid, s, kInk);
  } else if (c.coloring == Coloring::Labels) {
    if (c.labels <= 1) return;  // one colour (a remesh under its edges): nothing to key
    int x = margin;
    for (int64_t k = 0; k < std::min<int64_t>(c.labels, 8); ++k, x += swatch + 2 * s) {
      fill_rect(img, x, y, x + swatch, y + swatch, label_colour(k));
      frame_rect(img, x, y, x + swatch, y + swatch);
    }
    draw_text(img, x + 2 * s, y, std::to_string(c.labels) + (c.labels == 1 ? " label" : " labels") + ", one colour each",
              s, kInk);
  } else {
    fill_rect(img, margin, y, margin + swatch, y + swatch, {0.95, 0.95, 0.92});
    fill_rect(img, margin + swatch, y, margin + 2 * swatch, y + swatch, {0.75, 0.18, 0.15});
    frame_rect(img, margin, y, margin + 2 * swatch, y + swatch);
    draw_text(img, margin + 2 * swatch + 6 * s, y, "one square = " + legend_number(c.cell) + " in (u, v)", s, kInk);
  }
}

}  // namespace locus
