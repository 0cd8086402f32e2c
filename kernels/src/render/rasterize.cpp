// Software rasterizer for previews (kernels/include/locus/kernels/render/rasterize.hpp).
//
// Two passes: the first scans every triangle into a z-buffer that keeps, per
// pixel, the face and two barycentric coordinates; the second shades each
// covered pixel from those. Shading once per pixel (not per fragment) keeps the
// cost at O(faces' pixel area) + O(pixels).
#include "locus/kernels/render/rasterize.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/manifold_sheets.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/render/colour_map.hpp"
#include "locus/kernels/render/preview_annotations.hpp"
#include "locus/kernels/render/preview_camera.hpp"

namespace locus {

namespace {

using Vec3 = std::array<double, 3>;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 normalized(const Vec3& a) {
  const double l = std::sqrt(dot(a, a));
  return l > 0 ? Vec3{a[0] / l, a[1] / l, a[2] / l} : Vec3{0, 0, 0};
}

using Triangles = std::vector<std::array<int32_t, 3>>;

// Fan triangles of every face with valid ids.
Triangles fan_triangles(const Mesh& m, int64_t nv) {
  Triangles tris;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto fv = m.face(f);
    bool ok = fv.size() >= 3;
    for (int32_t v : fv) ok = ok && v >= 0 && v < nv;
    if (!ok) continue;
    for (size_t k = 1; k + 1 < fv.size(); ++k) tris.push_back({fv[0], fv[k], fv[k + 1]});
  }
  return tris;
}

// View-space positions vp (preview_camera.hpp: x right, y up, z towards the
// viewer) and screen positions sp3 (x right, y down, depth = view z, larger is
// nearer), the used vertices' box filling 90% of the smaller side of the W x H
// picture. False when no used vertex is finite.
struct Projection {
  PreviewCamera cam;
  double scale = 1, cx = 0, cy = 0;
  int W = 0, H = 0;
  Vec3 view(const Vec3& p) const {
    const Vec3 d = sub(p, cam.centre);
    return {dot(d, cam.right), dot(d, cam.up), dot(d, cam.back)};
  }
  Vec3 screen(const Vec3& v) const { return {0.5 * W + (v[0] - cx) * scale, 0.5 * H - (v[1] - cy) * scale, v[2]}; }
};

bool project(const Mesh& m, const Triangles& tris, const RasterOptions& opt, int W, int H, Projection& pr,
             std::vector<Vec3>& vp, std::vector<Vec3>& sp3) {
  const int64_t nv = m.num_vertices();
  pr.cam = principal_axes_camera(m, opt.view);
  pr.W = W;
  pr.H = H;
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  vp.resize(static_cast<size_t>(nv));
  std::vector<uint8_t> used(static_cast<size_t>(nv), 0);
  for (const auto& t : tris)
    for (int32_t v : t) used[v] = 1;
  for (int64_t v = 0; v < nv; ++v) {
    vp[v] = pr.view({m.x[v], m.y[v], m.z[v]});
    if (!used[v]) continue;
    for (int d = 0; d < 3; ++d)
      if (std::isfinite(vp[v][d])) {
        lo[d] = std::min(lo[d], vp[v][d]);
        hi[d] = std::max(hi[d], vp[v][d]);
      }
  }
  if (!(hi[0] >= lo[0]) || !(hi[1] >= lo[1])) return false;  // no finite vertex
  const double sx = hi[0] - lo[0], sy = hi[1] - lo[1];
  pr.scale = sx > 0 || sy > 0 ? 0.9 * std::min(sx > 0 ? W / sx : 1e300, sy > 0 ? H / sy : 1e300) : 1.0;
  pr.cx = 0.5 * (lo[0] + hi[0]);
  pr.cy = 0.5 * (lo[1] + hi[1]);
  sp3.resize(static_cast<size_t>(nv));
  for (int64_t v = 0; v < nv; ++v) sp3[v] = pr.screen(vp[v]);
  return true;
}

// Area-weighted vertex normals in view space.
std::vector<Vec3> vertex_normals(const Triangles& tris, const std::vector<Vec3>& vp) {
  std::vector<Vec3> normal(vp.size(), Vec3{0, 0, 0});
  for (const auto& t : tris) {
    const Vec3 n = cross(sub(vp[t[1]], vp[t[0]]), sub(vp[t[2]], vp[t[0]]));
    if (!std::isfinite(n[0] + n[1] + n[2])) continue;
    for (int32_t v : t)
      for (int d = 0; d < 3; ++d) normal[v][d] += n[d];
  }
  for (Vec3& n : normal) n = normalized(n);
  return normal;
}

// Pass 1: per pixel the nearest triangle and two of its barycentrics.
struct ZBuffer {
  std::vector<double> depth;
  std::vector<int32_t> face;  // -1: background
  std::vector<float> bary;    // 2 per pixel
};

void scan_triangle(const Vec3& a, const Vec3& b, const Vec3& c, int32_t ti, int W, int H, ZBuffer& zb) {
  const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  if (!(std::abs(area) > 1e-12) || !std::isfinite(area + a[2] + b[2] + c[2])) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a[0], b[0], c[0]}))));
  const int x1 = std::min(W - 1, static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a[1], b[1], c[1]}))));
  const int y1 = std::min(H - 1, static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]}))));
  for (int y = y0; y <= y1; ++y) {
    const double py = y + 0.5;
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5;
      // Barycentrics from the edge functions (any winding).
      const double w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
      const double w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
      const double w2 = 1 - w0 - w1;
      if (w0 < 0 || w1 < 0 || w2 < 0) continue;
      const double z = w0 * a[2] + w1 * b[2] + w2 * c[2];
      const size_t p = static_cast<size_t>(y) * W + x;
      if (z > zb.depth[p]) {
        zb.depth[p] = z;
        zb.face[p] = ti;
        zb.bary[2 * p] = static_cast<float>(w0);
        zb.bary[2 * p + 1] = static_cast<float>(w1);
      }
    }
  }
}

ZBuffer scan_triangles(const Triangles& tris, const std::vector<Vec3>& sp3, int W, int H) {
  const size_t npix = static_cast<size_t>(W) * H;
  ZBuffer zb;
  zb.depth.assign(npix, -std::numeric_limits<double>::infinity());
  zb.face.assign(npix, -1);
  zb.bary.assign(2 * npix, 0.f);
  for (size_t ti = 0; ti < tris.size(); ++ti)
    scan_triangle(sp3[tris[ti][0]], sp3[tris[ti][1]], sp3[tris[ti][2]], static_cast<int32_t>(ti), W, H, zb);
  return zb;
}

// Ranges for the colourings: Scalar maps [vmin, vmin + vspan] onto the colour
// map, Checker cells of side `cell` start at (umin, wmin).
struct ColorRanges {
  double vmin = 0, vspan = 1, umin = 0, wmin = 0, cell = 1;
  double vmax = -1;       // Scalar: largest finite value (< vmin: none)
  bool clipped_low = false, clipped_high = false;  // Scalar: values beyond the colour range
  bool missing = false;   // some vertex has no value
  int64_t labels = 0;     // Labels: distinct non-negative labels
};

ColorRanges color_ranges(std::span<const double> values, int64_t nv, const RasterOptions& opt) {
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  double umin = vmin, umax = -vmin, wmin = vmin, wmax = -vmin;
  ColorRanges cr;
  if (opt.coloring == Coloring::Scalar) {
    for (double v : values)
      if (std::isfinite(v)) {
        vmin = std::min(vmin, v);
        vmax = std::max(vmax, v);
      } else {
        cr.missing = true;
      }
  } else if (opt.coloring == Coloring::Labels) {
    std::vector<int64_t> seen;
    for (double v : values)
      if (std::isfinite(v) && v >= 0) seen.push_back(std::llround(std::min(v, 9.0e15)));
      else cr.missing = true;
    std::sort(seen.begin(), seen.end());
    cr.labels = std::unique(seen.begin(), seen.end()) - seen.begin();
  } else if (opt.coloring == Coloring::Checker) {
    for (int64_t v = 0; v < nv; ++v) {
      const double u = values[2 * v], w = values[2 * v + 1];
      if (!std::isfinite(u) || !std::isfinite(w)) {
        cr.missing = true;
        continue;
      }
      umin = std::min(umin, u);
      umax = std::max(umax, u);
      wmin = std::min(wmin, w);
      wmax = std::max(wmax, w);
    }
  }
  if (opt.coloring == Coloring::Scalar && opt.clip > 0 && vmax > vmin) {
    // Quantiles of the finite values: a few extreme vertices (finger tips in a
    // heat kernel signature) would otherwise leave the rest in one colour.
    std::vector<double> finite;
    for (double v : values)
      if (std::isfinite(v)) finite.push_back(v);
    std::sort(finite.begin(), finite.end());
    const size_t k = static_cast<size_t>(std::min(opt.clip, 0.49) * static_cast<double>(finite.size() - 1));
    const double lo = finite[k], hi = finite[finite.size() - 1 - k];
    if (hi > lo) {
      cr.clipped_low = lo > vmin;
      cr.clipped_high = hi < vmax;
      vmin = lo;
      vmax = hi;
    }
  }
  cr.vmin = vmin;
  cr.vmax = vmax;
  cr.vspan = vmax > vmin ? vmax - vmin : 1.0;
  const double uvspan = std::max(umax - umin, wmax - wmin);
  cr.cell = uvspan > 0 && std::isfinite(uvspan) ? uvspan / opt.checker_cells : 1.0;
  cr.umin = umin;
  cr.wmin = wmin;
  return cr;
}

// Unshaded colour of a pixel of triangle t at barycentrics w.
Vec3 surface_color(const std::array<int32_t, 3>& t, const double w[3], std::span<const double> values,
                   const RasterOptions& opt, const ColorRanges& cr) {
  const Vec3 grey = kNoValueGrey;
  Vec3 col = grey;
  if (opt.coloring == Coloring::Scalar) {
    double s = 0;
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      ok = ok && std::isfinite(values[t[k]]);
      s += w[k] * values[t[k]];
    }
    if (ok) col = scalar_colour((s - cr.vmin) / cr.vspan, opt.bands);
  } else if (opt.coloring == Coloring::Labels) {
    const int k = w[0] >= w[1] && w[0] >= w[2] ? 0 : (w[1] >= w[2] ? 1 : 2);
    const double label = values[t[k]];
    col = std::isfinite(label) ? label_colour(static_cast<int64_t>(std::llround(std::clamp(label, -1.0, 9.0e15))))
                               : grey;
  } else {
    double u = 0, v = 0;
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      ok = ok && std::isfinite(values[2 * t[k]]) && std::isfinite(values[2 * t[k] + 1]);
      u += w[k] * values[2 * t[k]];
      v += w[k] * values[2 * t[k] + 1];
    }
    if (ok) {
      const int64_t cu = static_cast<int64_t>(std::floor((u - cr.umin) / cr.cell));
      const int64_t cv = static_cast<int64_t>(std::floor((v - cr.wmin) / cr.cell));
      col = (cu + cv) % 2 == 0 ? Vec3{0.95, 0.95, 0.92} : Vec3{0.75, 0.18, 0.15};
    }
  }
  return col;
}

// Pass 2: shade each covered pixel once (interpolated normal, two-sided Lambert).
void shade_pixels(const ZBuffer& zb, const Triangles& tris, const std::vector<Vec3>& normal,
                  std::span<const double> values, const RasterOptions& opt, const ColorRanges& cr, RasterImage& img) {
  const Vec3 light = normalized({-0.35, 0.45, 1.0});
  const size_t npix = zb.face.size();
  for (size_t p = 0; p < npix; ++p) {
    if (zb.face[p] < 0) continue;
    const auto& t = tris[zb.face[p]];
    const double w[3] = {zb.bary[2 * p], zb.bary[2 * p + 1], 1.0 - zb.bary[2 * p] - zb.bary[2 * p + 1]};
    Vec3 n{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) n[d] += w[k] * normal[t[k]][d];
    n = normalized(n);
    const double shade = 0.28 + 0.72 * std::abs(dot(n, light));
    const Vec3 col = surface_color(t, w, values, opt, cr);
    for (int d = 0; d < 3; ++d)
      img.rgb[3 * p + d] = static_cast<uint8_t>(std::lround(std::clamp(col[d] * shade, 0.0, 1.0) * 255));
  }
}

// Wireframe: darkens pixels closer than 0.8 pixel to an edge of their triangle
// (barycentric w_k times the screen height of corner k over its edge).
void draw_edges(const ZBuffer& zb, const Triangles& tris, const std::vector<Vec3>& sp3, RasterImage& img) {
  const size_t npix = zb.face.size();
  for (size_t p = 0; p < npix; ++p) {
    if (zb.face[p] < 0) continue;
    const auto& t = tris[zb.face[p]];
    const Vec3 &a = sp3[t[0]], &b = sp3[t[1]], &c = sp3[t[2]];
    const double area2 = std::abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    const double w[3] = {zb.bary[2 * p], zb.bary[2 * p + 1], 1.0 - zb.bary[2 * p] - zb.bary[2 * p + 1]};
    const Vec3* q[3] = {&a, &b, &c};
    bool near = false;
    for (int k = 0; k < 3; ++k) {
      const Vec3 &u = *q[(k + 1) % 3], &v = *q[(k + 2) % 3];
      const double len = std::hypot(u[0] - v[0], u[1] - v[1]);
      near = near || (len > 0 && w[k] * area2 / len < 0.8);
    }
    if (near)
      for (int d = 0; d < 3; ++d) img.rgb[3 * p + d] = static_cast<uint8_t>(img.rgb[3 * p + d] / 4);
  }
}

// Markers over the picture: radius from the number of markers (a few sources
// large, hundreds of sites small); a marker behind the surface (deeper than
// the z-buffer by more than 1% of the picture's depth range at each of its 3 x 3
// pixels) is a ring only.
// Returns how many are hidden.
size_t draw_markers(const std::vector<Vec3d>& markers, const Projection& pr, const ZBuffer& zb, RasterImage& img) {
  size_t n_hidden = 0;
  if (markers.empty()) return 0;
  double zlo = std::numeric_limits<double>::infinity(), zhi = -zlo;
  for (double z : zb.depth)
    if (std::isfinite(z)) zlo = std::min(zlo, z), zhi = std::max(zhi, z);
  const double tol = zhi > zlo ? 0.01 * (zhi - zlo) : 0.0;
  const double side = std::min(pr.W, pr.H);
  const double r = std::clamp(0.25 * side / std::sqrt(static_cast<double>(markers.size())) * 0.2, 2.5, side / 80.0 + 2);
  for (const Vec3d& p : markers) {
    if (!std::isfinite(p[0] + p[1] + p[2])) continue;
    const Vec3 q = pr.screen(pr.view(p));
    const int px = static_cast<int>(std::floor(q[0])), py = static_cast<int>(std::floor(q[1]));
    // Hidden only when every covered pixel around it is nearer (a marker on a
    // silhouette or a boundary corner stays visible).
    bool hidden = true;
    for (int dy = -1; dy <= 1 && hidden; ++dy)
      for (int dx = -1; dx <= 1 && hidden; ++dx) {
        const int x = px + dx, y = py + dy;
        if (x < 0 || y < 0 || x >= pr.W || y >= pr.H) {
          hidden = false;
          break;
        }
        const double z = zb.depth[static_cast<size_t>(y) * pr.W + x];
        hidden = std::isfinite(z) && q[2] < z - tol;
      }
    draw_marker(img, q[0], q[1], r, hidden);
    n_hidden += hidden;
  }
  return n_hidden;
}

}  // namespace

// A mesh whose faces disagree in orientation (or that is not a manifold) is
// drawn as its manifold sheets, oriented per sheet: its area-weighted vertex
// normals would otherwise cancel where the faces disagree. Values follow the
// sheets' vertices.
static bool draw_as_sheets(const Mesh& m) {
  if (!m.is_triangle_mesh() || m.num_faces() == 0) return false;
  const MeshReport r = analyze_mesh(m);
  return r.non_manifold_edges > 0 || r.non_manifold_vertices > 0;
}

RasterImage rasterize_mesh(const Mesh& m, std::span<const double> values, const RasterOptions& opt) {
  if (draw_as_sheets(m)) {
    const ManifoldSheets sh = manifold_sheets(m);
    const size_t per = m.num_vertices() > 0 ? values.size() / static_cast<size_t>(m.num_vertices()) : 0;
    std::vector<double> sv;
    sv.reserve(per * sh.vertex_of.size());
    if (per * static_cast<size_t>(m.num_vertices()) == values.size())
      for (const int32_t v : sh.vertex_of)
        for (size_t k = 0; k < per; ++k) sv.push_back(values[per * static_cast<size_t>(v) + k]);
    if (sv.size() == per * sh.vertex_of.size() && sh.mesh.num_faces() > 0) return rasterize_mesh(sh.mesh, sv, opt);
  }
  if (opt.width < 1 || opt.height < 1 || opt.width > 16384 || opt.height > 16384)
    fail(ErrorCode::BadUsage, "rasterize: image size " + std::to_string(opt.width) + " x " +
                                  std::to_string(opt.height) + " is outside 1..16384");
  const int64_t nv = m.num_vertices();
  const int64_t per_vertex = opt.coloring == Coloring::Checker ? 2 : 1;
  if (static_cast<int64_t>(values.size()) != per_vertex * nv)
    fail(ErrorCode::BadUsage, "rasterize: " + std::to_string(values.size()) + " values for " + std::to_string(nv) +
                                  " vertices (expected " + std::to_string(per_vertex * nv) + ")");
  const int W = opt.width, H = opt.height;
  RasterImage img;
  img.width = W;
  img.height = H;
  img.rgb.assign(static_cast<size_t>(W) * H * 3, 242);
  // The picture takes the rows above the legend.
  const int legend_h = legend_height(W, H, opt.title);
  const int PH = std::max(1, H - legend_h);

  const ColorRanges cr = color_ranges(values, nv, opt);
  const Triangles tris = fan_triangles(m, nv);
  std::vector<Vec3> vp, sp3;
  Projection pr;
  size_t hidden_markers = 0;
  if (nv > 0 && !tris.empty() && project(m, tris, opt, W, PH, pr, vp, sp3)) {
    const std::vector<Vec3> normal = vertex_normals(tris, vp);
    const ZBuffer zb = scan_triangles(tris, sp3, W, PH);
    shade_pixels(zb, tris, normal, values, opt, cr, img);
    if (opt.edges) draw_edges(zb, tris, sp3, img);
    hidden_markers = draw_markers(opt.markers, pr, zb, img);
  }
  const std::string marker_label = opt.markers.empty() || opt.marker_label.empty() ? std::string()
                                   : hidden_markers > 0 ? opt.marker_label + " (ring: behind)"
                                                        : opt.marker_label;
  const LegendContent lc{.title = opt.title, .coloring = opt.coloring, .vmin = cr.vmin, .vmax = cr.vmax,
                         .bands = opt.bands, .clipped_low = cr.clipped_low, .clipped_high = cr.clipped_high,
                         .labels = cr.labels, .cell = cr.cell, .missing = cr.missing, .marker_label = marker_label};
  draw_legend(img, PH, lc);
  return img;
}

}  // namespace locus
