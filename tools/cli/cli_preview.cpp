// --preview / --view and the preview images (cli_preview.hpp).
#include "tools/cli/cli_preview.hpp"
#include "tools/cli/written_files.hpp"

#include <charconv>
#include <cmath>
#include <optional>

#include "locus/error.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/io/file_extension.hpp"
#include "locus/io/write_png.hpp"
#include "locus/kernels/render/rasterize.hpp"
#include "tools/cli/cli_report.hpp"

namespace locus::cli {

void add_preview_option(CLI::App* app, PreviewOptions& preview) {
  app->add_option("--preview", preview.path,
                  "Render a PNG of the mesh coloured by the result, with a legend and markers (800x800)")
      ->check(output_file({"png"}));
  app->add_option("--view", preview.view,
                  "Preview camera side as x,y,z (the camera looks from that side towards the mesh); default: from "
                  "the mesh's principal axes, upright for y-up and z-up files");
}

void check_preview_path(const std::string& path) {
  if (path.empty()) return;
  if (io::lower_extension(path) != "png") fail(ErrorCode::BadUsage, "--preview " + path + ": the preview is a PNG image; name it *.png");
  io::check_output_path(path);
}

namespace {

std::optional<std::array<double, 3>> parse_view(const std::string& text) {
  if (text.empty()) return std::nullopt;
  std::array<double, 3> d{};
  size_t at = 0;
  int k = 0;
  bool ok = true;
  for (; k < 3 && ok; ++k) {
    const size_t end = k < 2 ? text.find(',', at) : text.size();
    if (end == std::string::npos) {
      ok = false;
      break;
    }
    const std::string part = text.substr(at, end - at);
    const char* first = part.data();
    auto [ptr, ec] = std::from_chars(first, first + part.size(), d[k]);
    ok = !part.empty() && ec == std::errc() && ptr == first + part.size() && std::isfinite(d[k]);
    at = end + 1;
  }
  if (!ok || k != 3 || !(d[0] != 0 || d[1] != 0 || d[2] != 0))
    fail(ErrorCode::BadUsage, "--view '" + text + "': expected three numbers x,y,z, not all zero (e.g. 0,0,1: look from +z)");
  return d;
}

}  // namespace

void check_preview_options(const PreviewOptions& preview) {
  check_preview_path(preview.path);
  parse_view(preview.view);
  if (!preview.view.empty() && preview.path.empty()) fail(ErrorCode::BadUsage, "--view sets the camera of --preview; give --preview FILE.png too");
}

std::string preview_path_with(const std::string& path, const std::string& suffix) {
  const size_t dot = path.rfind('.');
  const size_t slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + suffix;
  return path.substr(0, dot) + suffix + path.substr(dot);
}

void write_preview(const Mesh& m, std::span<const double> values, PreviewKind kind, const PreviewOptions& preview,
                   const PreviewContent& content, const std::string& path_override) {
  const std::string path = path_override.empty() ? preview.path : path_override;
  if (path.empty()) return;
  check_preview_path(path);
  RasterOptions ro;
  ro.coloring = kind == PreviewKind::Scalar   ? Coloring::Scalar
                : kind == PreviewKind::Labels ? Coloring::Labels
                                              : Coloring::Checker;
  ro.view = parse_view(preview.view);
  ro.title = content.title;
  ro.markers = content.markers;
  ro.marker_label = content.marker_label;
  ro.edges = content.edges;
  ro.clip = content.clip;
  const RasterImage img = rasterize_mesh(m, values, ro);
  write_png(path, img.width, img.height, img.rgb);
  report_preview(path);
  log_written(path);
}

}  // namespace locus::cli
