// Quality of a Voronoi tessellation of a mesh (thesis §3.7.1, Table 3.7.1):
// the dual triangulation of the cells and its smallest interior angles, and the
// spread of the cell areas.
//
// Dual triangulation: one triangle per Voronoi corner, i.e. per mesh triangle whose
// three vertices carry three different labels, joining the three sites (their
// positions in R^3); label triples found in several mesh triangles (a corner that
// the discrete labels split) count once. For each dual triangle the smallest
// interior angle phi_m; reported: min and mean of phi_m in degrees (the thesis
// reports means of 50.6-53.6 degrees after 100 iterations, 60 is the equilateral
// optimum). Angles are those of the R^3 chords between the sites: at thin parts the
// chord across can be much shorter than the way along the surface, so the minimum
// angle is often set by two sites close across a thin part (docs/cvt.md).
// Cell areas: the lumped mass of the cell's vertices (one third of the incident
// triangle areas, kernels/mesh_operators), in the mesh's own R^3 metric. Reported:
// the coefficient of variation std/mean and the variance of area / total area
// (the thesis's "variance in cell area" on meshes scaled to unit area).
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/kernels/heat/surface_point.hpp"

namespace locus {

struct CvtQuality {
  int64_t dual_triangles = 0;
  double min_angle_deg = 0;   // min over dual triangles of the smallest angle (0 if none)
  double mean_angle_deg = 0;  // mean over dual triangles of the smallest angle
  std::array<int32_t, 3> min_angle_sites{-1, -1, -1};  // sites of the dual triangle with the min angle
  std::array<int64_t, 12> angle_histogram{};  // dual triangles per 5-degree bin of the smallest angle
  double area_cv = 0;         // std / mean of the cell areas (population std)
  double area_variance = 0;   // variance of cell area / total area
  int64_t empty_cells = 0;
  std::vector<double> cell_area;
};

// Spread of given cell areas (e.g. LloydResult::cell_area from split triangles):
// cv = std / mean (population std), variance of area / total area.
void cell_area_spread(std::span<const double> area, double& cv, double& variance);

// label[v] in [0, sites.size()); throws BadUsage otherwise.
CvtQuality cvt_quality(const Mesh& m, std::span<const int32_t> label, std::span<const SurfacePoint> sites);

}  // namespace locus
