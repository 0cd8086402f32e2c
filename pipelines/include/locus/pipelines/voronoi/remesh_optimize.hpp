// Angle optimization of a remesh on its input surface (thesis §3.7.1): the dual of
// the heat CVT is already well shaped (~48 degrees mean smallest angle on
// armadillo), but its vertices are the cells' heat centroids and its
// connectivity that of discrete cells (a Voronoi edge shorter than the input's
// edges can come out flipped); rounds of
//   (1) edge flips, in the first and last round by the Delaunay criterion (an
//       interior edge whose opposite angles sum to more than 180 degrees, when
//       the smaller smallest angle of its two triangles grows), in the rounds
//       between by valence (towards 6 inside, 4 on the boundary, as isotropic
//       remeshing does; no new angle below min(old, 20 degrees)); every flip
//       needs the two triangles nearly coplanar (normals within 30 degrees),
//       and its new edge must not exist yet;
//   (2) tangential smoothing: each interior vertex moves, in its tangent
//       plane, to the mean of its ring's vertices (each once per incident
//       triangle; it beat the area-weighted centroid of the triangles and the
//       ODT circumcenter mean on armadillo, docs/cvt.md), then back onto
//       the input (nearest point, triangle_grid.hpp); a move is kept only if no
//       incident triangle turns over and the input's normal there agrees with
//       the vertex normal (so a vertex never jumps across a thin part); tips
//       and ridges (an incident triangle more than 60 degrees off the vertex
//       normal) stay unless one of their triangles has an angle below 10
//       degrees, which keeps the Hausdorff distance near the dual's;
//   (3) after the rounds, a targeted angle repair: each (non-boundary)
//       vertex of a triangle with an angle below 30 degrees climbs,
//       tangentially and projected onto the input, to the position where the
//       smallest angle of its own triangles is largest, then Delaunay flips;
//       at claw and ear tips this opens the tip's angle mostly by moving its
//       neighbors; tips and ridges themselves move at most a tenth of an edge
//       per sweep (so the Hausdorff distance stays; docs/cvt.md); sweeps
//       until one changes nothing;
//   (4) sweeps in which every free vertex climbs the same way to the largest
//       sum of its triangles' smallest angles (what the mean smallest angle
//       adds up), never taking a triangle of its ring below min(the ring's
//       smallest angle, 30 degrees; tips and ridges within a tenth of an edge
//       of where the smoothing left them; off flat parts no edge from the
//       vertex longer than its longest was, unless the ring's chord error,
//       its edge midpoints' and centroids' distance to the input, does not
//       grow); then the repair (3) again;
//   (5) where a triangle below 25 degrees is left, the repair (3) on those
//       triangles' vertices with tips reaching 0.3 of an edge per sweep;
// raise the mean smallest angle by ~7 degrees and the smallest by ~20 on
// armadillo (docs/cvt.md). Neither step changes the topology: flips keep every edge in two triangles and never duplicate an
// edge; moves change no connectivity. Boundary vertices move only along the
// input's boundary curves (remesh_boundary.hpp): after each smoothing pass
// towards the arclength midpoint of their boundary neighbors, after each
// angle pass to the position along the curve with the largest smallest angle.
// Pinned vertices (RemeshOptimizeOptions::pinned: on the input's features)
// do not move, but along their feature curve (RemeshOptimizeOptions::slides)
// as boundary vertices along the boundary, and an edge between two
// consecutive vertices of a curve does not flip (remesh_flips.hpp).
//
// Deterministic: flips visit edges in a fixed order; moves are computed from
// the previous positions (Jacobi) and applied together.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/remesh_features.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

struct RemeshOptimizeOptions {
  int rounds = 6;  // flip + smooth rounds (a final flip pass follows)
  // The smoothing moves a tip or ridge vertex only when one of its triangles
  // has an angle below this (docs/cvt.md: 20 cut armadillo's tips at 5,000
  // sites, 10 keeps them; the angle repair below handles the rest).
  double unpin_below_deg = 10;
  // Then sweeps of the targeted angle repair: the vertices of triangles with
  // an angle below angle_below_deg climb to the largest smallest angle of
  // their triangles, followed by Delaunay flips (0 sweeps: off). Tips and
  // ridges move at most tip_reach mean edges (of their own) from where the
  // smoothing left them (0: never), which bounds the Hausdorff distance added.
  // The repair stops after the first sweep that changes nothing.
  int angle_sweeps = 8;
  double angle_below_deg = 30;
  double tip_reach = 0.12;
  // Then sweeps over every free vertex climbing to the largest sum of its
  // triangles' smallest angles (no ring's smallest angle below
  // min(itself, angle_below_deg)), and the repair once more (0: off;
  // docs/cvt.md: +2 to +3 degrees of mean smallest angle at 1,000 sites).
  int sum_sweeps = 3;
  // A climb of the sum keeps the longest edge from the vertex at most this
  // times its value when the climb starts, unless the vertex's triangles are
  // all within 20 degrees of its normal or the ring's chord error (the
  // largest distance from an edge midpoint or a triangle's centroid to the
  // input) does not grow (0: no bound; the chord rule lets climbs along
  // cylinders and CAD faces lengthen edges: turbine's mean smallest angle
  // 49.8 -> 50.1 degrees, docs/cvt.md). 1 keeps the
  // Hausdorff distance of the smoothing; 0 raises the mean smallest angle
  // ~0.7 degrees more and the median Hausdorff distance of the sample meshes
  // at 1,000 sites from 1.4% to 1.6% of the diagonal (docs/cvt.md).
  double sum_edge_growth = 1;
  // Last, where triangles below hard_below_deg are left (a tip folded against
  // its neighbor across a thin part; the graded fan around a tiny hole), the
  // repair on their vertices only, tips reaching hard_tip_reach of an edge
  // per sweep, at most hard_sweeps sweeps (0, or angle_sweeps 0: off).
  // Meshes without such triangles are untouched (docs/cvt.md: man 22.3 ->
  // 30.0 degrees, ChineseDragon-10kv 13.1 -> 23.0).
  double hard_below_deg = 25;
  double hard_tip_reach = 0.3;
  int hard_sweeps = 30;
  // Per remesh vertex (empty: none): 1 where the vertex stays (a feature's,
  // remesh_features.hpp); without slides, an edge between two such
  // vertices never flips.
  std::vector<uint8_t> pinned{};
  // Feature curves whose pinned vertices slide along them as boundary
  // vertices do along the boundary (FeatureCurve with remesh vertex ids in
  // `site`; remesh_boundary.hpp add_curve). Empty: they stay.
  std::vector<FeatureCurve> slides{};
};

struct RemeshOptimizeStats {
  int64_t flips = 0;
  int64_t moves = 0;     // vertex moves kept, all rounds
  int64_t angle_moves = 0;  // moves of the targeted angle repair
  int64_t boundary_moves = 0;  // moves of boundary (and feature) vertices along the input's curves
  int64_t refused = 0;   // moves refused (a triangle would turn over, or the projection crossed a thin part)
  RemeshOptimizeStats& operator+=(const RemeshOptimizeStats& o) {  // the counts of a later pass
    flips += o.flips, moves += o.moves, angle_moves += o.angle_moves;
    boundary_moves += o.boundary_moves, refused += o.refused;
    return *this;
  }
};

// `remesh` is a triangle mesh whose vertices lie on `input` (grid built over it).
RemeshOptimizeStats optimize_remesh(const Mesh& input, const TriangleGrid& grid, Mesh& remesh,
                                    const RemeshOptimizeOptions& opt = {});

}  // namespace locus
