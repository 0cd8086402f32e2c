// The colours of the previews, shared by the rasterizer and
// the legend drawn under the picture so that the colour bar shows exactly the
// colours on the surface.
//  * scalar_colour: a blue -> teal -> green -> yellow map of s in [0, 1]
//    (perceptually ordered, still readable in grey), with alternating
//    light/dark bands (`bands` of them, 0 = smooth) that act as iso-lines.
//  * label_colour: one colour per integer label (golden-ratio hues, saturation
//    and value alternating so neighbouring labels with close hues differ);
//    negative = grey (no label).
#pragma once
#include <array>
#include <cstdint>

namespace locus {

using Rgb = std::array<double, 3>;  // components in [0, 1]

Rgb scalar_colour(double s, int bands);
Rgb label_colour(int64_t label);

inline constexpr Rgb kNoValueGrey{0.62, 0.62, 0.62};

}  // namespace locus
