// Triangulating polygon faces (quads and polygons from DCC
// tools into the triangle-only pipelines of chapters 3-6; chapter 2's polygon
// Laplacians, polygon_laplacian.hpp, need no triangulation).
//
// Ear clipping in the polygon's best-fit plane: the corners are projected on
// the plane of the Newell normal (the area vector of the closed polygon,
// exact for planar polygons and a least-squares-like fit for warped ones), so
// a non-planar quad triangulates like its projection. Non-convex polygons are
// handled (an ear is a convex corner whose triangle holds no other corner,
// on its boundary included); among the ears the one with the largest
// smallest angle is cut first (polygons up to 32 corners; larger ones cut the
// first ear), which for a quad picks the diagonal that makes the better pair.
//
// Refused with Error(BadInput) naming the face (`where`): a polygon without
// area (corners collinear or coincident) and one whose projected boundary
// crosses or touches itself (a bow-tie) — the triangles would not cover it.
// Deterministic; O(k^2) per polygon of k corners for the checks, O(k^3) worst
// case for the ear search on large non-convex polygons.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

// The k - 2 triangles of one polygon as corner indices 0..k-1, each oriented
// like the polygon (counter-clockwise about its Newell normal). k = 3 returns
// {0, 1, 2} without checks (degenerate triangles are mesh_topology's concern).
std::vector<std::array<int32_t, 3>> triangulate_polygon(std::span<const std::array<double, 3>> corners,
                                                         const std::string& where);

struct TriangulatedMesh {
  Mesh mesh;                     // the same vertices; triangles only (triangles of the input kept as they are)
  std::vector<int32_t> face_of;  // per triangle: the input face it belongs to
};

// Triangulates every face of m with more than 3 corners; `name` goes into
// messages ("face 12 of NAME ..."). Faces keep their order; a polygon's
// triangles are consecutive.
TriangulatedMesh triangulate_polygons(const Mesh& m, const std::string& name);

}  // namespace locus
