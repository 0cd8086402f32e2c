// What a preview says besides the coloured surface (a colour
// bar with the quantity and its range, markers for sources, centres and
// sites): the legend strip under the picture and the marker symbol.
// Drawn by rasterize_mesh (rasterize.hpp); exposed for its tests.
#pragma once
#include <cstdint>
#include <string>

#include "locus/kernels/render/rasterize.hpp"

namespace locus {

struct LegendContent {
  std::string title;
  Coloring coloring = Coloring::Scalar;
  double vmin = 0, vmax = 0;  // Scalar: the range (vmin > vmax: no finite value)
  int bands = 0;              // Scalar: bands of the colour bar, as on the surface
  bool clipped_low = false, clipped_high = false;  // Scalar: some values lie beyond the range ("<=", ">=")
  int64_t labels = 0;         // Labels: number of distinct non-negative labels
  double cell = 0;            // Checker: side of one square in (u, v) units
  bool missing = false;       // some vertex has no value: a grey "no value" swatch
  std::string marker_label;   // "" = no marker in the legend
};

// Rows of the image the legend takes (0 for an empty title), and the text scale (pixels per font pixel).
int legend_height(int width, int height, const std::string& title);
int legend_text_scale(int width);

// Draws the legend into rows [top, img.height).
void draw_legend(RasterImage& img, int top, const LegendContent& c);

// A white disk of radius r with a dark ring at (x, y); `hidden`: the ring only.
void draw_marker(RasterImage& img, double x, double y, double r, bool hidden);

// "0.0123", "1.5e+07": %.4g, the way the legend writes numbers.
std::string legend_number(double v);

}  // namespace locus
