// Uniform grid of triangles, nearest-point queries
// (pipelines/include/locus/pipelines/voronoi/triangle_grid.hpp).
#include "locus/pipelines/voronoi/triangle_grid.hpp"

#include <algorithm>
#include <cmath>

#include "remesh_vec3.hpp"

namespace locus {

namespace {
using namespace remesh_vec3;
V3 axpy(const V3& a, double s, const V3& d) { return {a[0] + s * d[0], a[1] + s * d[1], a[2] + s * d[2]}; }
}  // namespace

V3 closest_point_on_triangle(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return axpy(a, d1 / (d1 - d3), ab);
  const V3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return axpy(a, d2 / (d2 - d6), ac);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return axpy(b, (d4 - d3) / ((d4 - d3) + (d5 - d6)), sub(c, b));
  const double denom = 1.0 / (va + vb + vc);
  return axpy(axpy(a, vb * denom, ab), vc * denom, ac);
}

TriangleGrid::TriangleGrid(const Mesh& m) : m_(m) {
  const int32_t nf = m.num_faces();
  for (int c = 0; c < 3; ++c) {
    lo_[c] = INFINITY;
    hi_[c] = -INFINITY;
  }
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const V3 p = pos(m, v);
    for (int c = 0; c < 3; ++c) {
      lo_[c] = std::min(lo_[c], p[c]);
      hi_[c] = std::max(hi_[c], p[c]);
    }
  }
  if (m.num_vertices() == 0)
    for (int c = 0; c < 3; ++c) lo_[c] = hi_[c] = 0;
  const double ext = std::max({hi_[0] - lo_[0], hi_[1] - lo_[1], hi_[2] - lo_[2], 1e-300});
  // A surface of nf triangles in a box of side ext: about nf^(1/2) triangles
  // across, so cells of ext / sqrt(nf / 8) hold a few triangles each (cells
  // of ext / sqrt(nf / 4) made the remesh's projections ~10% slower: docs/cvt.md).
  const double across = std::clamp(std::sqrt(std::max(nf, 1) / 8.0), 1.0, 512.0);
  cell_ = ext / across;
  for (int c = 0; c < 3; ++c) dim_[c] = std::max(1, static_cast<int>((hi_[c] - lo_[c]) / cell_) + 1);
  // Only cells the surface passes are stored (about nf / 8 of the ~(nf / 8)^1.5
  // cells of the box: 33 million at 832k triangles): an open-addressing table
  // from cell number to its run of faces.
  auto each_cell = [&](int32_t f, auto&& g) {
    const auto fv = m.face(f);
    int lo[3], hi[3];
    for (int c = 0; c < 3; ++c) {
      double a = INFINITY, b = -INFINITY;
      for (int32_t v : fv) {
        const double x = c == 0 ? m.x[v] : c == 1 ? m.y[v] : m.z[v];
        a = std::min(a, x);
        b = std::max(b, x);
      }
      lo[c] = index(c, a);
      hi[c] = index(c, b);
    }
    for (int i = lo[0]; i <= hi[0]; ++i)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int k = lo[2]; k <= hi[2]; ++k) g((static_cast<uint64_t>(i) * dim_[1] + j) * dim_[2] + k);
  };
  // Sized for twice the cells expected; long thin triangles (a cylinder's
  // sides, each as tall as the mesh) pass many more, so a pass that fills
  // half the table starts again with twice the slots: probing always ends.
  size_t slots = 16;
  while (slots < 2 * static_cast<size_t>(std::max(nf, 1))) slots *= 2;
  std::vector<int64_t> count;
  for (bool fits = false; !fits; slots *= 2) {
    keys_.assign(slots, kEmpty);
    count.assign(slots, 0);
    size_t used = 0;
    fits = true;
    for (int32_t f = 0; f < nf && fits; ++f)
      each_cell(f, [&](uint64_t c) {
        if (!fits) return;
        const size_t q = slot_of(c, true);
        if (count[q]++ == 0 && 2 * ++used > slots) fits = false;
      });
    if (fits) break;
  }
  offsets_.assign(slots + 1, 0);
  for (size_t q = 0; q < slots; ++q) offsets_[q + 1] = offsets_[q] + count[q];
  faces_.resize(static_cast<size_t>(offsets_[slots]));
  for (size_t q = 0; q < slots; ++q) count[q] = offsets_[q];
  for (int32_t f = 0; f < nf; ++f) each_cell(f, [&](uint64_t c) { faces_[count[slot_of(c, false)]++] = f; });
}

// The table slot of cell c (linear probing); with insert, an empty slot found
// takes c; without, kNone when c holds no face.
size_t TriangleGrid::slot_of(uint64_t c, bool insert) {
  const size_t mask = keys_.size() - 1;
  for (size_t q = (c * 0x9E3779B97F4A7C15ull) >> 20 & mask;; q = (q + 1) & mask) {
    if (keys_[q] == c) return q;
    if (keys_[q] == kEmpty) {
      if (!insert) return kNone;
      keys_[q] = c;
      return q;
    }
  }
}

size_t TriangleGrid::find(uint64_t c) const {
  const size_t mask = keys_.size() - 1;
  for (size_t q = (c * 0x9E3779B97F4A7C15ull) >> 20 & mask;; q = (q + 1) & mask) {
    if (keys_[q] == c) return q;
    if (keys_[q] == kEmpty) return kNone;
  }
}

int TriangleGrid::index(int c, double x) const {
  const double f = std::floor((x - lo_[c]) / cell_);
  return static_cast<int>(std::clamp(f, 0.0, static_cast<double>(dim_[c] - 1)));
}

ClosestPoint TriangleGrid::closest(const V3& p) const {
  ClosestPoint best;
  double best2 = INFINITY;
  int ci[3];
  double out2 = 0;  // squared distance from p to the grid's box
  for (int c = 0; c < 3; ++c) {
    ci[c] = index(c, p[c]);
    const double d = std::max({lo_[c] - p[c], p[c] - hi_[c], 0.0});
    out2 += d * d;
  }
  const int maxr = std::max({dim_[0], dim_[1], dim_[2]});
  for (int r = 0; r <= maxr; ++r) {
    // Cells of shell r or farther are at least (r - 1) cells from p (p inside its
    // clamped cell; outside the box, the box distance adds in quadrature at least).
    const double shell = std::max(0, r - 1) * cell_;
    if (best2 < INFINITY && best2 <= shell * shell + out2) break;
    for (int i = std::max(0, ci[0] - r); i <= std::min(dim_[0] - 1, ci[0] + r); ++i)
      for (int j = std::max(0, ci[1] - r); j <= std::min(dim_[1] - 1, ci[1] + r); ++j)
        for (int k = std::max(0, ci[2] - r); k <= std::min(dim_[2] - 1, ci[2] + r); ++k) {
          if (std::max({std::abs(i - ci[0]), std::abs(j - ci[1]), std::abs(k - ci[2])}) != r) continue;
          if (best2 < INFINITY) {  // a cell farther than the best triangle cannot hold a nearer one
            const int ijk[3] = {i, j, k};
            double box2 = 0;
            for (int a = 0; a < 3; ++a) {
              const double lo = lo_[a] + ijk[a] * cell_, hi = lo + cell_;
              const double d = std::max({lo - p[a], p[a] - hi, 0.0});
              box2 += d * d;
            }
            if (box2 > best2) continue;
          }
          const size_t c = find((static_cast<uint64_t>(i) * dim_[1] + j) * dim_[2] + k);
          if (c == kNone) continue;
          for (int64_t q = offsets_[c]; q < offsets_[c + 1]; ++q) {
            const auto fv = m_.face(faces_[q]);
            for (size_t t = 1; t + 1 < fv.size(); ++t) {
              const V3 x = closest_point_on_triangle(p, pos(m_, fv[0]), pos(m_, fv[t]), pos(m_, fv[t + 1]));
              const V3 d = sub(p, x);
              const double d2 = dot(d, d);
              if (d2 < best2 || (d2 == best2 && faces_[q] < best.face)) {  // ties: lowest face (deterministic)
                best2 = d2;
                best.point = x;
                best.face = faces_[q];
              }
            }
          }
        }
  }
  best.distance = std::sqrt(best2);
  return best;
}

}  // namespace locus
