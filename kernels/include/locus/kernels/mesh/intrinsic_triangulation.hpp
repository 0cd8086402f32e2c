// An intrinsic triangulation in flat arrays (DESIGN.md "Data"): triangles known
// only by their vertex ids and edge lengths, glued side to side, as the tufted
// cover (tufted_cover.hpp) builds it and intrinsic Delaunay flips
// (intrinsic_delaunay.hpp) change it. Sharp & Crane, "A Laplacian for
// Nonmanifold Triangle Meshes" (SGP 2020), §3-4; the cotan formulas are the
// thesis' eq. 3.5 and 3.6 written with lengths instead of positions.
//
// Side s (a "halfedge") of face f = s / 3 runs from vertex[s] to vertex[next(s)];
// twin[s] is the side of the neighbouring face glued to it (running the other
// way), length[s] == length[twin[s]]. Every side has a twin: the surface is closed.
// Vertex ids are those of the input mesh; several corners of one vertex may lie on
// different sheets (the tufted cover has two sheets over a manifold mesh), and an
// edge may join a vertex to itself after flips.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "locus/core/host_allocator.hpp"

namespace locus {

struct IntrinsicTriangulation {
  int32_t num_vertices = 0;         // of the input mesh (ids in vertex[] are below it)
  HostVector<int32_t> vertex;       // 3 * num_faces: tail vertex of each side
  HostVector<int32_t> twin;         // 3 * num_faces: the side glued to it
  HostVector<double> length;        // 3 * num_faces: intrinsic length of each side
  int32_t num_faces() const { return static_cast<int32_t>(vertex.size() / 3); }
};

inline int32_t side_next(int32_t s) { return s % 3 == 2 ? s - 2 : s + 1; }
inline int32_t side_prev(int32_t s) { return s % 3 == 0 ? s + 2 : s - 1; }

// Area of a triangle with side lengths a, b, c (Heron in Kahan's stable form:
// exact for needles); 0 when the lengths violate the triangle inequality.
inline double intrinsic_triangle_area(double a, double b, double c) {
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);  // a >= b >= c
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return p > 0.0 ? 0.25 * std::sqrt(p) : 0.0;
}

// Cotangent of the angle opposite side c in a triangle of area `area`:
// (a^2 + b^2 - c^2) / (4 area).
inline double intrinsic_cotan(double a, double b, double c, double area) {
  return (a * a + b * b - c * c) / (4.0 * area);
}

// Cotangent of the angle of face s / 3 opposite side s.
inline double cotan_opposite(const IntrinsicTriangulation& T, int32_t s) {
  const double a = T.length[side_next(s)], b = T.length[side_prev(s)], c = T.length[s];
  return intrinsic_cotan(a, b, c, intrinsic_triangle_area(a, b, c));
}

}  // namespace locus
