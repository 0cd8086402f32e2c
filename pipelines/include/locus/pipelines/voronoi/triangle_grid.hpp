// Nearest point on a triangle mesh through a uniform grid over its triangles
// (for the remesh's Hausdorff distance and the projection of its vertices
// back onto the input during the optimization of remesh_optimize.hpp).
//
// Each triangle (polygons as fans) is listed in every cell its bounding box
// overlaps; cells are about two triangles wide, and only the cells the surface
// passes are stored (a hash table: the box has ~(nf / 8)^1.5 cells). A query scans shells of cells
// around the point's cell, nearest first, until the next shell is farther than
// the best triangle found, so the answer is exact. Immutable after
// construction: queries may run concurrently.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

struct ClosestPoint {
  std::array<double, 3> point{0, 0, 0};
  int32_t face = -1;     // the face holding it (-1 when the mesh has none)
  double distance = 0;
};

class TriangleGrid {
 public:
  explicit TriangleGrid(const Mesh& m);  // m must outlive the grid
  ClosestPoint closest(const std::array<double, 3>& p) const;
  double distance(const std::array<double, 3>& p) const { return closest(p).distance; }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t{0};
  static constexpr size_t kNone = ~size_t{0};
  int index(int c, double x) const;
  size_t slot_of(uint64_t cell, bool insert);
  size_t find(uint64_t cell) const;
  const Mesh& m_;
  double lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0}, cell_ = 1;
  int dim_[3] = {1, 1, 1};
  std::vector<uint64_t> keys_;    // hash table of the non-empty cells (kEmpty: free slot)
  std::vector<int64_t> offsets_;  // per slot: its faces in faces_
  std::vector<int32_t> faces_;
};

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection §5.1.5).
std::array<double, 3> closest_point_on_triangle(const std::array<double, 3>& p, const std::array<double, 3>& a,
                                                const std::array<double, 3>& b, const std::array<double, 3>& c);

}  // namespace locus
