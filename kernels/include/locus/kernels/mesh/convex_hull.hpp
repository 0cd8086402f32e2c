// Exact convex hull of points in 3D with integer coordinates (used by
// make_random_sphere; not from the thesis).
//
// Randomized incremental construction with conflict lists (Clarkson-Shor;
// every point outside the current hull is filed under one face it sees): insert
// the points in the given order (callers pass them in random order for the
// expected O(n log n) bound), delete the faces the new point sees, and cone the
// horizon to the point. The orientation predicate is exact: a floating-point
// filter first, then an exact evaluation in 192-bit integers, so the hull is
// combinatorially correct for every input, including nearly coplanar points.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace locus {

// Largest |coordinate| convex_hull_3d accepts: differences stay below 2^53, so they
// are exact both as int64 and as double.
inline constexpr int64_t kConvexHullMaxCoordinate = int64_t(1) << 52;

// Sign (+1, 0, -1) of det[b - a, c - a, d - a]: +1 when d lies on the side the
// normal (b - a) x (c - a) points to. Exact for |coordinates| <= 2^52.
int orient3d_exact(const int64_t a[3], const int64_t b[3], const int64_t c[3], const int64_t d[3]);

// Hull triangles as 3*nt vertex indices into the input, oriented counter-clockwise
// seen from outside. Points inside the hull, or duplicating a hull vertex, are not
// referenced. Only exactly coplanar (collinear) input points can give coplanar
// neighboring faces (zero-area triangles); points on a sphere never do. Throws BadInput when fewer than 4 points are given, a coordinate exceeds
// kConvexHullMaxCoordinate, or all points are coplanar.
std::vector<int32_t> convex_hull_3d(std::span<const int64_t> x, std::span<const int64_t> y,
                                    std::span<const int64_t> z);

}  // namespace locus
