// Heat centroids of surface regions (thesis §3.5, eqs. 3.24-3.29, heat source
// eqs. 3.10/3.11) and their refinement off the vertices (§3.7.1 "Centroids on faces").
//
// The centroid of a cell C is the hottest point after diffusing C's indicator:
// (M - t L_C) u = M chi_C (eq. 3.7 with h = chi_C, i.e. eq. 3.10 up to the cell area,
// which does not move the maximum), whose right-hand side is the lumped mass at
// C's vertices. The discrete maximum is a vertex; to let Lloyd's generators move
// smoothly, a bivariate quadratic is fitted (least squares) to the heat at the
// hottest vertex and its one-ring (two-ring when the one-ring gives fewer than six
// values), in the tangent plane of the area-weighted vertex normal; its maximizer is
// located in the projected incident triangles and mapped back by barycentric
// coordinates (the closest point of those triangles when it lies outside them; the
// vertex itself when the quadratic has no maximum). Optionally (sigma > 0) the
// maximizer is refined once by a Gaussian-weighted refit centered at it, which makes
// the centroid vary more smoothly with the cell (Lloyd jitters less; docs/cvt.md).
//
// Thread safety: CentroidGeometry is immutable; all functions are re-entrant.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"
#include "locus/kernels/heat/heat_batch.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"

namespace locus {

struct CentroidGeometry {
  int32_t n = 0;
  HostVector<int64_t> vf_offsets;  // n + 1: faces incident to each vertex (CSR), ascending
  HostVector<int32_t> vf_faces;    // (the fits' area-weighted normals are summed over these when needed)
  Adjacency own_adj;                // the adjacency when built here
  const Adjacency* borrowed = nullptr;
  const Adjacency& adj() const { return borrowed ? *borrowed : own_adj; }
};
CentroidGeometry prepare_centroid_geometry(const Mesh& m);
// The same with m's vertex adjacency already built (MeshDerived::adjacency):
// borrowed, not copied (13 MB at 416k vertices), so it must outlive the result.
CentroidGeometry prepare_centroid_geometry(const Mesh& m, const Adjacency& adjacency);

struct HeatCentroid {
  SurfacePoint point;       // refined centroid (or the hottest vertex)
  int32_t hottest = -1;     // hottest vertex
  bool refined = false;     // the quadratic had a maximum and the point moved off the vertex
  int32_t fit_points = 0;   // values used by the fit
};

// Quadratic refinement around `hottest`, with heat values given at every vertex
// the fit may read (heat[v]; localized callers scatter their kept values and leave
// zeros elsewhere). `rings` (1..4): fit to the hottest vertex and its rings up to
// that graph distance (the thesis fits the one ring; more rings average the
// piecewise-linear heat over a wider patch). `sigma` > 0: the maximizer of that fit
// is refined by a second fit of the same values, weighted by a Gaussian of width
// sigma times the mean projected one-ring distance centered at the first maximizer
// (the fit's values far from the maximum count less); 0 = the unweighted fit only.
HeatCentroid refine_heat_maximum(const Mesh& m, const CentroidGeometry& g, std::span<const double> heat,
                                 int32_t hottest, int rings = 1, double sigma = 0.0);
// The same reading lane `lane` of an 8-lane solution kept at some vertices:
// heat(v) = values8[pos[v] * 8 + lane] where pos[v] >= 0, zero elsewhere (pos has
// one entry per vertex; the hottest vertex must be kept). Lets a localized caller
// refine all 8 lanes of a batch without scattering each lane into a dense vector.
HeatCentroid refine_heat_maximum(const Mesh& m, const CentroidGeometry& g, std::span<const double> values8,
                                 std::span<const int32_t> pos, int lane, int32_t hottest, int rings = 1,
                                 double sigma = 0.0);

// One-shot: full solve of the cell indicator, hottest vertex, refinement (if `refine`).
// `cell` lists vertex ids (non-empty, valid).
HeatCentroid heat_centroid(const HeatDiffusion& H, const Mesh& m, const CentroidGeometry& g,
                           std::span<const int32_t> cell, bool refine);

// The discrete maxima of an 8-lane batch solution (Lloyd's centroid step): the
// hottest kept vertex of every lane in one pass, largest heat, smallest id on
// ties (deterministic); -1 for a batch without kept vertices.
void hottest_vertices(const HeatBatch& hb, int32_t best[kLanes]);

// The centroid's bias diagnostic (LloydResult::centroid_bias). area_centroid:
// sum_i b_i x_i / sum_i b_i, the exact area centroid (R^3) of a cell whose load is
// w at vertices ids (the hat functions reproduce x on every triangle); the origin
// for a load summing to 0. tangential_distance: |q - p| with the component along
// the surface normal at p removed (p's face normal, or the vertex normal of g).
void area_centroid(const Mesh& m, std::span<const int32_t> ids, std::span<const double> w, double out[3]);
double tangential_distance(const Mesh& m, const CentroidGeometry& g, const SurfacePoint& p, const double q[3]);

}  // namespace locus
