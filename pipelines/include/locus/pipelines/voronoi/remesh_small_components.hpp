// Components of a remesh that are one triangle take the triangle of their
// input component when that is one triangle too (thesis §3.7.1). The dual
// puts a boundary cell's vertex on an input boundary vertex of its run; on a
// subdivided level a one-triangle component's loop has six vertices, and its
// three cells can take two corners and the midpoint between them (b9_mesh: a
// triangle of zero area). The boundary optimization never moves a vertex
// across a sharp corner of the loop, so nothing opens it. A component of one
// input triangle has no better remesh than that triangle (any triangulation
// of it keeps an angle at most its smallest), so its three corners are put
// back, in the input's order. Positions only: the topology does not change.
#pragma once
#include <cstdint>

#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

// Returns the remesh components set to their input triangle (`grid` over `input`).
int32_t restore_single_triangles(const Mesh& input, const TriangleGrid& grid, Mesh& remesh);

}  // namespace locus
