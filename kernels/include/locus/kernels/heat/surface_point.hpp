// Points on a triangle mesh given by a face and barycentric weights (or a vertex):
// the generators, sites and heat sources of the heat-diffusion pipelines (thesis
// §3.2, eqs. 3.7, 3.8: the source of a point is its hat-function weights).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

// A point on a triangle mesh: barycentric weights (summing to 1) of the corners
// f0[face], f1[face], f2[face], or a vertex when face < 0.
struct SurfacePoint {
  int32_t face = -1;
  int32_t vertex = -1;
  std::array<double, 3> bary{1.0, 0.0, 0.0};
};
inline SurfacePoint vertex_point(int32_t v) { return SurfacePoint{-1, v, {1.0, 0.0, 0.0}}; }
// Throws BadUsage naming `what` and `index` unless p is a vertex or a face of m with
// finite barycentric weights >= -1e-9 summing to 1 (within 1e-9).
void check_surface_point(const Mesh& m, const SurfacePoint& p, const char* what, size_t index);
// Position in R^3.
std::array<double, 3> surface_point_position(const Mesh& m, const SurfacePoint& p);
// Hat-function weights of p: up to 3 (vertex, weight) pairs with weight > 0; returns the count.
int surface_point_support(const Mesh& m, const SurfacePoint& p, int32_t v[3], double w[3]);

// `count` points uniformly distributed by area (face chosen with probability
// proportional to its area, barycentric weights uniform on the triangle), from a
// splitmix64 stream seeded with `seed`: the same on every platform.
std::vector<SurfacePoint> random_surface_points(const Mesh& m, int32_t count, uint64_t seed);

}  // namespace locus
