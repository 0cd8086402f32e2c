// Surface points across one 1:4 midpoint subdivision (subdivide_midpoint,
// mesh_generators.hpp): the remesh's repair (cvt_remesh.hpp) falls back to a
// subdivided copy of the input when its cells, unions of input vertices, are
// too coarse to split a defect (thesis §3.7.1: the closed-ball property needs
// cells that resolve every interface). Midpoint subdivision keeps the surface
// point for point, so a site keeps its position, and the original vertices keep
// their ids (a label of the fine mesh restricted to them is a label of m).
//
// Child faces of face f = (a, b, d) with midpoints ab, bd, da: 4f = (a, ab, da),
// 4f+1 = (ab, b, bd), 4f+2 = (da, bd, d), 4f+3 = (ab, bd, da).
#pragma once
#include <span>
#include <vector>

#include "locus/kernels/heat/surface_point.hpp"
#include "locus/mesh.hpp"

namespace locus {

// Points of the triangle mesh m as points of subdivide_midpoint(m, 1) (same positions).
std::vector<SurfacePoint> refine_surface_points(const Mesh& m, std::span<const SurfacePoint> p);
// Points of fine = subdivide_midpoint(m, 1) as points of m (same positions).
std::vector<SurfacePoint> coarsen_surface_points(const Mesh& m, const Mesh& fine, std::span<const SurfacePoint> p);

}  // namespace locus
