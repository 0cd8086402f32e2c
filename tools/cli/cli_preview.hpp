// Previews (--preview out.png [--view x,y,z]; kernels/render/rasterize.hpp,
// io/write_png.hpp): a shaded picture of the mesh coloured by a per-vertex
// result, seen from its principal axes (preview_camera.hpp) or from --view,
// with a legend strip (the quantity, its range or labels, the marker) and
// markers at sources, centres or sites; 800 x 800.
#pragma once
#include <array>
#include <span>
#include <string>
#include <vector>

#include "locus/mesh.hpp"
#include "tools/cli/cli_command_table.hpp"

namespace locus::cli {

// Usage:
//   PreviewOptions preview;                         // member of the command's options
//   add_preview_option(app, preview);               // at registration: --preview and --view
//   check_preview_options(preview);                 // before reading the mesh (BadUsage unless "" or *.png, bad --view)
//   write_preview(mesh, values, PreviewKind::Scalar, preview, {"distance from vertex 3", {p}, "source"});
//                                                   // after computing; no-op when preview.path == ""
enum class PreviewKind {
  Scalar,   // values: nv numbers (distance, adf, ...), colour map from min to max with iso-bands; NaN = no value (grey)
  Labels,   // values: nv integer labels (cvt cells), one distinct colour per label, negative = grey
  Checker,  // values: 2 nv numbers, (u, v) per vertex interleaved; a checkerboard of the UVs, NaN = grey
};
struct PreviewOptions {
  std::string path;  // --preview FILE.png ("" = none)
  std::string view;  // --view x,y,z: the camera's side ("" = from the principal axes)
};
struct PreviewContent {
  std::string title;                        // the quantity (legend)
  std::vector<std::array<double, 3>> markers;  // sources, centres, sites
  std::string marker_label;                 // what the markers are ("source", "sites")
  bool edges = false;                       // draw the triangle edges (remesh)
  double clip = 0;                          // Scalar: colours span the clip..1-clip quantiles (rasterize.hpp)
};
void add_preview_option(CLI::App* app, PreviewOptions& preview);
void check_preview_path(const std::string& path);
// check_preview_path and --view's grammar (three numbers, not all zero).
void check_preview_options(const PreviewOptions& preview);
// `FILE.png` with `suffix` before the extension ("x.png", "-t0" -> "x-t0.png"):
// the names of several images from one --preview (hks: one per t).
std::string preview_path_with(const std::string& path, const std::string& suffix);
// Renders and writes the PNG to `path` (default preview.path) (Error(BadUsage)
// if values has the wrong size, Error(BadInput) if the file cannot be
// written); logs "wrote <path>".
void write_preview(const Mesh& m, std::span<const double> values, PreviewKind kind, const PreviewOptions& preview,
                   const PreviewContent& content, const std::string& path = "");

}  // namespace locus::cli
