// Boundary vertices of a remesh sliding along its input's boundary curves
// (and, added by add_curve, a feature's vertices along its feature curve)
// (thesis §3.7.1; the boundary side of remesh_optimize.hpp). The dual puts a
// boundary cell's vertex on an input boundary vertex of its run, so the spacing
// along a loop follows the cells, not the curve, and the triangles at the
// boundary come out thin. Here each remesh boundary vertex is located on the
// input's boundary polyline (loop, arclength) and moves only along it:
//   smoothing: to the arclength midpoint of its two boundary neighbors (a 1-D
//              Lloyd step: uniform spacing along the loop between corners);
//   angles:    a 1-D pattern search for the position that maximizes the
//              smallest angle of its own triangles.
// Sharp corners of the input's boundary (turning more than 45 degrees, as
// restricted_dual.hpp) are never crossed; a vertex on one stays. A move is kept
// only when no incident triangle turns over and, for smoothing, the smallest
// angle of its triangles stays above min(its value before, 20 degrees); the
// angle search only raises it. So the vertices stay on the input's boundary
// curve and in their order along it, and the connectivity does not change.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

class BoundaryCurves {
 public:
  // Locates every boundary vertex of `remesh` on the boundary loops of `input`
  // (nearest point). A remesh loop whose vertices do not lie, in order, on one
  // input loop keeps its vertices where they are.
  BoundaryCurves(const Mesh& input, const Mesh& remesh);
  // One Gauss-Seidel sweep over the remesh's boundary loops (F: its current
  // triangles); by_angle selects the angle search instead of the smoothing.
  // Returns the number of moves kept.
  int64_t sweep(Mesh& remesh, const std::vector<std::array<int32_t, 3>>& F, bool by_angle);
  int64_t movable() const;  // boundary vertices that may move
  // A feature curve's vertices (remesh_features.hpp), sliding the same way:
  // polyline p (closed or open), vertices v at arclengths u (increasing,
  // from p[0]); an open curve's first and last vertex stay (its corners).
  void add_curve(const std::vector<std::array<double, 3>>& p, bool closed, std::vector<int32_t> v,
                 std::vector<double> u);
  // Vertex c (on no run) joins the run where a and b are neighbors, between
  // them, at the arclength that splits their gap as c's distances to them
  // do, and moves onto the curve there. False (nothing changed) when no run
  // has a and b as neighbors.
  bool adopt(Mesh& remesh, int32_t a, int32_t b, int32_t c);

 private:
  struct Curve {  // one input loop: positions, cumulative arclength, corner arclengths
    std::vector<std::array<double, 3>> p;
    std::vector<double> s;  // s[i] at p[i]; s.back() = length (p closes on p[0])
    std::vector<double> corners;
  };
  struct Run {  // one remesh loop on one curve: vertices and their unwrapped arclength u (increasing)
    int32_t curve = -1;
    double dir = 1;  // position at arclength dir * u
    bool closed = true;  // false: an open feature curve (its ends are corners)
    std::vector<int32_t> v;
    std::vector<double> u;
    std::vector<uint8_t> pinned;
  };
  std::array<double, 3> at(const Curve& c, double s) const;
  std::vector<Curve> curves_;
  std::vector<Run> runs_;
};

}  // namespace locus
