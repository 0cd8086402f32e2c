// A small software rasterizer for previews:
// the mesh seen from the camera of preview_camera.hpp (its principal axes, or
// a given direction), coloured by a per-vertex result, Lambert-shaded, with a
// legend under the picture and markers at given points.
//
// Camera: orthographic, scaled so that the projected mesh fills 90% of the
// picture area (the image above the legend). Visibility: a z-buffer; ties
// keep the earlier face, so the image does not depend on anything but the
// input. Shading: per-pixel interpolated vertex normals (area-weighted), one
// light from the upper left of the viewer, two-sided (|n.l|, so
// inconsistently oriented faces are lit too), plus ambient. Polygons are
// drawn as triangle fans.
//
// Colourings (values per vertex, interpolated across faces; colour_map.hpp):
//  * Scalar: nv values; the colour map from the smallest to the largest
//    finite value, with alternating light/dark bands (`bands` of them) that act
//    as iso-lines; NaN = no value (grey).
//  * Labels: nv integer labels; each pixel takes the label of the nearest corner
//    of its face, one colour per label; negative = grey.
//  * Checker: 2 nv values (u, v interleaved); a checkerboard with `checker_cells`
//    squares across the larger UV extent; NaN = grey.
// With `edges`, pixels within 0.8 pixel of their triangle's edges are darkened
// (the wireframe of a remesh over its shaded surface).
//
// Legend (when `title` is not empty; preview_legend.hpp): a strip under the
// picture with the title, and for Scalar a colour bar with the range's ends
// and middle written at its ends, for Labels the number of labels, for
// Checker the size of one square; a grey swatch when some value is missing;
// the marker symbol with `marker_label`.
// Markers: white dots with a dark ring at the given points (sources, centres,
// sites); a marker hidden behind the surface is drawn as a ring only.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "locus/kernels/render/preview_camera.hpp"
#include "locus/mesh.hpp"

namespace locus {

enum class Coloring { Scalar, Labels, Checker };

struct RasterOptions {
  int width = 800, height = 800;  // pixels
  Coloring coloring = Coloring::Scalar;
  int bands = 12;                 // Scalar: number of iso-bands (0 = smooth)
  double clip = 0;                // Scalar: the colours span the clip and 1 - clip quantiles of the finite
                                  // values (0: min to max); values beyond take the end colours (legend: <=, >=)
  double checker_cells = 12;      // Checker: squares across the UV extent
  bool edges = false;             // draw the (fan) triangle edges dark, about one pixel wide (remesh previews)
  std::optional<Vec3d> view;      // camera side (--view); none = from the principal axes
  std::string title;              // legend title ("" = no legend; the picture takes the whole image)
  std::vector<Vec3d> markers;     // points to mark (sources, centres, sites)
  std::string marker_label;       // what the markers are, for the legend ("source", "sites")
};

struct RasterImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3, rows top to bottom
};

// Error(BadUsage) when values has the wrong size for the colouring or the image
// size is not in 1..16384. Faces with out-of-range vertex ids are skipped
// (the mesh readers never produce them).
RasterImage rasterize_mesh(const Mesh& m, std::span<const double> values, const RasterOptions& opt = {});

}  // namespace locus
