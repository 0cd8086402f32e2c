// Test fixture: small planar meshes for the perfect-Laplacian tests (thesis §2.5):
// Delaunay triangulations (Bowyer–Watson) of seeded random points in a square and
// in a disk, random edge flips that keep every triangle valid, polygon meshes made
// by deleting interior edges, and the shadow of the Schönhardt polyhedron.
// Quadratic-time and exact enough for ~50 points; not library code.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include "locus/mesh.hpp"

namespace locus::test {

// splitmix64: the same numbers on every platform.
struct SplitMix {
  uint64_t s;
  explicit SplitMix(uint64_t seed) : s(seed) {}
  uint64_t next() {
    uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  size_t below(size_t n) { return static_cast<size_t>(next() % n); }
};

inline double orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

struct PlanarTriangulation {
  std::vector<double> x, y;
  std::vector<std::array<int32_t, 3>> tris;  // counter-clockwise
};

// Bowyer–Watson with a far super-triangle. The caller supplies the points whose
// convex hull is the domain (points on the boundary of a square or a circle), so
// the super-triangle never cuts hull edges off. With `power` weights w_i the
// in-circle test lifts points to x² + y² - w_i: the result is the regular
// (weighted Delaunay) triangulation of the points (points whose lift ends up
// above the lower hull are dropped and the others renumbered).
inline PlanarTriangulation delaunay(const std::vector<double>& px, const std::vector<double>& py,
                                   const std::vector<double>& power = {}) {
  const int32_t n = static_cast<int32_t>(px.size());
  PlanarTriangulation T;
  T.x = px;
  T.y = py;
  double lo_x = px[0], hi_x = px[0], lo_y = py[0], hi_y = py[0];
  for (int32_t i = 0; i < n; ++i) {
    lo_x = std::min(lo_x, px[i]);
    hi_x = std::max(hi_x, px[i]);
    lo_y = std::min(lo_y, py[i]);
    hi_y = std::max(hi_y, py[i]);
  }
  const double cx = 0.5 * (lo_x + hi_x), cy = 0.5 * (lo_y + hi_y);
  const double M = 1e3 * std::max(hi_x - lo_x, hi_y - lo_y);
  T.x.insert(T.x.end(), {cx - 2 * M, cx + 2 * M, cx});
  T.y.insert(T.y.end(), {cy - M, cy - M, cy + 2 * M});
  std::vector<std::array<int32_t, 3>> tris{{n, n + 1, n + 2}};
  // Lifted height relative to p: |a - p|^2 - (w_a - w_p) (the |a|^2 - |p|^2 form
  // differs by a linear function, which leaves the determinant unchanged).
  auto lift = [&](int32_t a, int32_t p, double dx, double dy) {
    const double wa = (a < n && !power.empty()) ? power[a] : 0.0, wp = power.empty() ? 0.0 : power[p];
    return dx * dx + dy * dy - (wa - wp);
  };
  auto in_circle = [&](const std::array<int32_t, 3>& t, int32_t p) {
    const double ax = T.x[t[0]] - T.x[p], ay = T.y[t[0]] - T.y[p];
    const double bx = T.x[t[1]] - T.x[p], by = T.y[t[1]] - T.y[p];
    const double qx = T.x[t[2]] - T.x[p], qy = T.y[t[2]] - T.y[p];
    const double det = lift(t[0], p, ax, ay) * (bx * qy - qx * by) - lift(t[1], p, bx, by) * (ax * qy - qx * ay) +
                       lift(t[2], p, qx, qy) * (ax * by - bx * ay);
    return det > 0;
  };
  for (int32_t p = 0; p < n; ++p) {
    std::vector<std::array<int32_t, 3>> keep;
    std::vector<std::pair<int32_t, int32_t>> cavity;  // directed edges of the bad triangles
    for (const auto& t : tris) {
      if (in_circle(t, p))
        for (int k = 0; k < 3; ++k) cavity.emplace_back(t[k], t[(k + 1) % 3]);
      else
        keep.push_back(t);
    }
    for (const auto& [a, b] : cavity) {
      bool shared = false;
      for (const auto& [c, d] : cavity)
        if (c == b && d == a) shared = true;
      if (!shared) keep.push_back({a, b, p});
    }
    tris.swap(keep);
  }
  for (const auto& t : tris)
    if (t[0] < n && t[1] < n && t[2] < n) T.tris.push_back(t);
  // Drop points that are in no triangle (hidden by their power) and renumber.
  std::vector<int32_t> id(static_cast<size_t>(n), -1);
  for (const auto& t : T.tris)
    for (int32_t v : t) id[v] = 0;
  int32_t k = 0;
  std::vector<double> x, y;
  for (int32_t i = 0; i < n; ++i)
    if (id[i] == 0) {
      id[i] = k++;
      x.push_back(T.x[i]);
      y.push_back(T.y[i]);
    }
  for (auto& t : T.tris)
    for (int32_t& v : t) v = id[v];
  T.x = std::move(x);
  T.y = std::move(y);
  return T;
}

// Power weights for a regular triangulation that is not Delaunay (thesis Fig. 2.1b):
// uniform in [0, sigma) at interior points, 0 on the boundary (first nb points).
inline std::vector<double> random_power(size_t n, size_t nb, double sigma, SplitMix& rng) {
  std::vector<double> w(n, 0.0);
  for (size_t i = nb; i < n; ++i) w[i] = sigma * rng.uniform();
  return w;
}

// n points in [0,1]^2: 16 on the boundary (the corners and 3 per side; the side
// points bulge out by 0.002 so the hull is strictly convex and no three boundary
// points are collinear) and n-16 uniform interior points. sigma > 0: regular
// triangulation with random power weights in [0, sigma) instead of Delaunay.
inline PlanarTriangulation random_square(int32_t n, SplitMix& rng, double sigma = 0.0) {
  std::vector<double> x, y;
  const double cx[4] = {0, 1, 1, 0}, cy[4] = {0, 0, 1, 1};
  for (int s = 0; s < 4; ++s) {
    const double ax = cx[s], ay = cy[s], bx = cx[(s + 1) % 4], by = cy[(s + 1) % 4];
    const double nx = by - ay, ny = ax - bx;  // outward normal of a counter-clockwise square
    for (int k = 0; k < 4; ++k) {
      const double t = (k + (k ? 0.1 * (rng.uniform() - 0.5) : 0.0)) / 4;
      const double bulge = 0.002 * 4 * t * (1 - t);
      x.push_back(ax + t * (bx - ax) + bulge * nx);
      y.push_back(ay + t * (by - ay) + bulge * ny);
    }
  }
  while (static_cast<int32_t>(x.size()) < n) {
    x.push_back(0.04 + 0.92 * rng.uniform());
    y.push_back(0.04 + 0.92 * rng.uniform());
  }
  return delaunay(x, y, sigma > 0 ? random_power(x.size(), 16, sigma, rng) : std::vector<double>{});
}

// 16 points near the unit circle (radius in [0.995, 1]: still in strictly convex
// position, but not cocircular, which would make the Delaunay triangulation
// ambiguous) and n-16 uniform points in the disk of radius 0.92.
inline PlanarTriangulation random_disk(int32_t n, SplitMix& rng, double sigma = 0.0) {
  std::vector<double> x, y;
  for (int k = 0; k < 16; ++k) {
    const double r = 1.0 - 0.005 * rng.uniform();
    x.push_back(r * std::cos(2 * std::numbers::pi * k / 16));
    y.push_back(r * std::sin(2 * std::numbers::pi * k / 16));
  }
  while (static_cast<int32_t>(x.size()) < n) {
    const double u = 2 * rng.uniform() - 1, v = 2 * rng.uniform() - 1;
    if (u * u + v * v > 1) continue;
    x.push_back(0.92 * u);
    y.push_back(0.92 * v);
  }
  return delaunay(x, y, sigma > 0 ? random_power(x.size(), 16, sigma, rng) : std::vector<double>{});
}

// Flips about `fraction` of the interior edges, one at a time, each only when the
// quadrilateral around it is strictly convex (so both new triangles stay valid).
// The result need not be regular (then no perfect Laplacian exists).
inline int flip_random_edges(PlanarTriangulation& T, double fraction, SplitMix& rng) {
  auto interior_edges = [&]() {
    std::vector<std::array<int32_t, 4>> out;  // (triangle, corner, other triangle, other corner)
    for (size_t t = 0; t < T.tris.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int32_t a = T.tris[t][k], b = T.tris[t][(k + 1) % 3];
        if (a > b) continue;
        for (size_t u = 0; u < T.tris.size(); ++u)
          for (int l = 0; l < 3; ++l)
            if (T.tris[u][l] == b && T.tris[u][(l + 1) % 3] == a)
              out.push_back({static_cast<int32_t>(t), k, static_cast<int32_t>(u), l});
      }
    return out;
  };
  const size_t target = static_cast<size_t>(fraction * static_cast<double>(interior_edges().size()) + 0.5);
  size_t done = 0;
  for (int attempt = 0; attempt < 20 * static_cast<int>(target) + 20 && done < target; ++attempt) {
    const auto E = interior_edges();
    const auto& q = E[rng.below(E.size())];
    // Triangle (a, b, c) and (b, a, d): replace the edge ab by cd.
    const auto t1 = T.tris[q[0]], t2 = T.tris[q[2]];
    const int32_t a = t1[q[1]], b = t1[(q[1] + 1) % 3], c = t1[(q[1] + 2) % 3], d = t2[(q[3] + 2) % 3];
    const double o1 = orient2d(T.x[a], T.y[a], T.x[d], T.y[d], T.x[c], T.y[c]);
    const double o2 = orient2d(T.x[d], T.y[d], T.x[b], T.y[b], T.x[c], T.y[c]);
    const double scale = (T.x[a] - T.x[b]) * (T.x[a] - T.x[b]) + (T.y[a] - T.y[b]) * (T.y[a] - T.y[b]);
    if (o1 <= 1e-6 * scale || o2 <= 1e-6 * scale) continue;
    T.tris[q[0]] = {a, d, c};
    T.tris[q[2]] = {d, b, c};
    ++done;
  }
  return static_cast<int>(done);
}

inline Mesh to_mesh(const PlanarTriangulation& T) {
  Mesh m;
  for (size_t i = 0; i < T.x.size(); ++i) m.add_vertex(T.x[i], T.y[i], 0.0);
  for (const auto& t : T.tris) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

// Deletes about `fraction` of the interior edges by merging the two faces on them,
// keeping every vertex at degree >= 3 and every face a simple cycle: faces become
// convex or non-convex polygons (thesis §2.5, "Polygon meshes").
inline Mesh remove_random_edges(const PlanarTriangulation& T, double fraction, SplitMix& rng) {
  std::vector<std::vector<int32_t>> faces;
  for (const auto& t : T.tris) faces.push_back({t[0], t[1], t[2]});
  const int32_t n = static_cast<int32_t>(T.x.size());
  auto degrees = [&]() {
    std::vector<std::vector<int32_t>> nb(static_cast<size_t>(n));
    for (const auto& f : faces)
      for (size_t k = 0; k < f.size(); ++k) {
        const int32_t a = f[k], b = f[(k + 1) % f.size()];
        nb[a].push_back(b);
        nb[b].push_back(a);
      }
    std::vector<int32_t> deg(static_cast<size_t>(n));
    for (int32_t v = 0; v < n; ++v) {
      std::sort(nb[v].begin(), nb[v].end());
      deg[v] = static_cast<int32_t>(std::unique(nb[v].begin(), nb[v].end()) - nb[v].begin());
    }
    return deg;
  };
  const size_t target = static_cast<size_t>(fraction * static_cast<double>(T.tris.size()));
  size_t done = 0;
  for (int attempt = 0; attempt < 50 * static_cast<int>(target) + 50 && done < target; ++attempt) {
    const size_t f1 = rng.below(faces.size());
    const size_t k = rng.below(faces[f1].size());
    const int32_t u = faces[f1][k], v = faces[f1][(k + 1) % faces[f1].size()];
    size_t f2 = faces.size(), l = 0;
    for (size_t g = 0; g < faces.size() && f2 == faces.size(); ++g)
      for (size_t j = 0; j < faces[g].size(); ++j)
        if (faces[g][j] == v && faces[g][(j + 1) % faces[g].size()] == u) {
          f2 = g;
          l = j;
        }
    if (f2 == faces.size()) continue;  // boundary edge
    const auto deg = degrees();
    if (deg[u] < 4 || deg[v] < 4) continue;
    // Merged cycle: f1 from v round to u, then f2 from u's successor round to v's predecessor.
    std::vector<int32_t> merged;
    const auto& A = faces[f1];
    const auto& B = faces[f2];
    for (size_t j = 0; j < A.size(); ++j) merged.push_back(A[(k + 1 + j) % A.size()]);  // v ... u
    for (size_t j = 2; j < B.size(); ++j) merged.push_back(B[(l + j) % B.size()]);      // after u, before v
    std::vector<int32_t> sorted = merged;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
    faces[f1] = merged;
    faces.erase(faces.begin() + static_cast<std::ptrdiff_t>(f2));
    ++done;
  }
  Mesh m;
  for (size_t i = 0; i < T.x.size(); ++i) m.add_vertex(T.x[i], T.y[i], 0.0);
  for (const auto& f : faces) m.add_face(f);
  return m;
}

// The shadow of the Schönhardt polyhedron (thesis Fig. 2.2): an outer triangle
// and an inner triangle rotated by `twist` radians inside it, the side quads split
// by diagonals from O_{i+1} to I_i. For twist < 0 these are the "twisted"
// diagonals of the Schönhardt polyhedron: a valid planar triangulation that is not
// regular (no lift makes it convex), so it admits no perfect Laplacian. For
// twist > 0 the same combinatorics is regular.
inline Mesh schoenhardt_shadow(double twist = -0.35, double inner = 0.4) {
  Mesh m;
  for (int i = 0; i < 3; ++i) {
    const double a = std::numbers::pi / 2 + 2 * std::numbers::pi * i / 3;
    m.add_vertex(std::cos(a), std::sin(a), 0.0);  // outer O_i
  }
  for (int i = 0; i < 3; ++i) {
    const double a = std::numbers::pi / 2 + 2 * std::numbers::pi * i / 3 + twist;
    m.add_vertex(inner * std::cos(a), inner * std::sin(a), 0.0);  // inner I_i = 3 + i
  }
  m.add_triangle(3, 4, 5);
  for (int i = 0; i < 3; ++i) {
    const int32_t o0 = i, o1 = (i + 1) % 3, i0 = 3 + i, i1 = 3 + (i + 1) % 3;
    m.add_triangle(o0, o1, i0);
    m.add_triangle(i0, o1, i1);
  }
  return m;
}

}  // namespace locus::test
