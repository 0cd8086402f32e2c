// Text in preview images (a legend with the quantity's name
// and range): a 5 x 9 pixel bitmap font of its own (digits, lower-case
// and upper-case letters, the punctuation numbers and names need), drawn at
// an integer scale; any other character as a box.
#pragma once
#include <array>
#include <cstdint>
#include <string_view>

#include "locus/kernels/render/rasterize.hpp"

namespace locus {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 9, kGlyphAdvance = 6;  // in font pixels

// Width in image pixels of `text` drawn at `scale`.
int text_width(std::string_view text, int scale);

// Draws `text` with its top-left corner at (x, y); pixels outside the image are clipped.
void draw_text(RasterImage& img, int x, int y, std::string_view text, int scale, const std::array<uint8_t, 3>& rgb);

}  // namespace locus
