// A last pass of an optimized remesh towards its input (thesis §3.7.1): the
// remesh's Hausdorff distance is made of the input's vertices farthest from
// the remesh (a tip or a crest between remesh vertices: on lion 1.9% of the
// bounding diagonal, against 1.6% from the remesh's triangles to the input;
// docs/cvt.md). The input vertices at least `candidates` times the farthest's
// distance, worst first, each pull a vertex of their nearest remesh triangle
// (the nearest first) towards them: all the way, or 3/4 ... 1/8, projected
// onto the input. A move is kept when the local two-sided distance falls
// (the input vertices whose nearest remesh triangle is one of the vertex's,
// the only ones that can get farther, to the triangles of the vertex and its
// ring; the vertex's edge midpoints and triangle centroids to the input),
// the input's normal there agrees with the
// ring's, no triangle of the ring turns more than 60 degrees or drops below
// min(the ring's smallest angle, `keep_deg`), and the mean smallest angle
// lost so far stays within `budget_deg` and above `mean_floor_deg`. Pinned and boundary
// vertices stay; connectivity does not change. The input vertices' nearest
// remesh triangles come from one grid query, then are updated around each
// move; a moved vertex's ring waits for the next pass; passes until one
// moves nothing. Sequential (deterministic).
#pragma once
#include <cstdint>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

struct RemeshFidelityOptions {
  int passes = 8;
  double candidates = 0.8;       // input vertices at least this times the farthest's distance
  double keep_deg = 30;          // no ring angle taken below min(itself, keep_deg)
  double budget_deg = 0.5;       // mean smallest angle all moves may spend together
  double mean_floor_deg = 50.5;  // ... never taking it below this
  std::vector<uint8_t> pinned;   // per remesh vertex, 1: stays (a feature's); empty: none
};

// `grid` is built over `input`; returns the vertex moves.
int64_t pull_to_input(const Mesh& input, const TriangleGrid& grid, Mesh& remesh,
                      const RemeshFidelityOptions& opt = {});

}  // namespace locus
