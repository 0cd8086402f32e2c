// A small software rasterizer for previews (issue 9 item 5): the mesh seen
// from a fixed camera, coloured by a per-vertex result, Lambert-shaded.
//
// Camera: orthographic, looking at the bounding-box center from -z turned by
// 30 degrees about y and tilted 20 degrees down (a three-quarter view; the
// CGAL armadillo faces -z, y up), scaled
// so that the projected mesh fills 90% of the smaller image side. Visibility:
// a z-buffer; ties keep the earlier face, so the image does not depend on
// anything but the input. Shading: per-pixel interpolated vertex normals
// (area-weighted), one light from the upper left of the viewer, two-sided
// (|n.l|, so inconsistently oriented faces are lit too), plus ambient.
// Polygons are drawn as triangle fans.
//
// Colourings (values per vertex, interpolated across faces):
//  * Scalar: nv values; a blue-green-yellow map from the smallest to the largest
//    finite value, with alternating light/dark bands (`bands` of them) that act
//    as iso-lines; NaN = no value (grey).
//  * Labels: nv integer labels; each pixel takes the label of the nearest corner
//    of its face, one colour per label (golden-ratio hues); negative = grey.
//  * Checker: 2 nv values (u, v interleaved); a checkerboard with `checker_cells`
//    squares across the larger UV extent; NaN = grey.
// With `edges`, pixels within 0.8 pixel of their triangle's edges are darkened
// (the wireframe of a remesh over its shaded surface, issue 23).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

enum class Coloring { Scalar, Labels, Checker };

struct RasterOptions {
  int width = 800, height = 800;  // pixels
  Coloring coloring = Coloring::Scalar;
  int bands = 12;                 // Scalar: number of iso-bands (0 = smooth)
  double checker_cells = 12;      // Checker: squares across the UV extent
  bool edges = false;             // draw the (fan) triangle edges dark, about one pixel wide (remesh previews)
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
