// CVT remeshing (thesis §3.7.1): Lloyd's method with heat cells and
// centroids (cvt_lloyd.hpp), then the restricted-Delaunay dual of the final
// cells (restricted_dual.hpp), made a manifold with the input's topology by
// adding sites where the cells break the closed-ball property.
//
// Repair rounds: while the partition has defects, one site is added at each
// defect's repair vertex, Lloyd runs `relax_iterations` more iterations on all
// sites (so the new cells take their share of the surface), and the labels of
// the final sites are checked again; at most `max_repair_rounds` rounds, the
// last one without relaxation. The isotropic operator is factored once and
// shared by every round (or taken from LloydOptions::prepared). With
// relax_iterations = 0 (the default; isotropic, localized solver) a round only
// adds sites: their heat is solved on Dijkstra balls of 2.5 expected cell radii
// and merged into the last diagram's top-K lists (heat_voronoi_add), instead
// of relabelling every site (docs/cvt.md).
//
// Refinement: cells are sets of input vertices, so where a cell spans only a
// few of them a defect can have no vertex left for a new site (each candidate
// holds one already), or the rounds run out. The sites then move, unchanged,
// onto a 1:4 midpoint subdivision of the mesh (the same surface; its own
// operator, t in units of its own h^2), are labelled there and repaired again
// (remesh_refinement.hpp); at most `max_refinements` times. The result's
// labels and sites are given on the input all the same.
//
// Last resort: where heat labels keep breaking the closed-ball property (the
// heat rounds leave more defects than they found, or the levels run out:
// needle fans of CAD tessellations), the repair starts again from Lloyd's
// sites with graph-geodesic labels (one multi-source Dijkstra): connected
// cells, and at worst every vertex a cell, whose dual is the level mesh, so
// the rounds end with a manifold dual (max_repair_rounds = 0: no repair).
//
// Density: the dual has a vertex per non-empty cell; density passes drop or
// split sites, relax and repair again until the count is within 1.5% of the
// request (or the passes stop helping; the topology may need more). A dual
// still more than 1.5% above the request loses its shortest edges to
// topology-keeping collapses (remesh_collapse.hpp).
//
// Features (feature_angle_deg > 0): after the density passes, sites on the
// input's creases and corners replace the Lloyd sites next to them, the
// cells are labelled again and repaired (remesh_features.hpp); the
// optimization keeps those sites' vertices where they are. An input without
// feature edges at that angle is remeshed as without the option.
//
// The manifold dual is then optimized on the input (remesh_optimize.hpp);
// where triangles below 25 degrees remain, their longest edges split (up to
// 1.5% above the request, remesh_split.hpp) and two optimization rounds
// follow, kept when the smallest angle grew. A remesh still off the angle
// targets (a triangle below 25 degrees, or the mean below 50) has vertices
// moved from its flat, wide regions to its thin ones (remesh_rebalance.hpp).
// A component of one triangle over an input component of one triangle is
// that triangle (remesh_small_components.hpp).
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/pipelines/voronoi/remesh_features.hpp"
#include "locus/pipelines/voronoi/remesh_optimize.hpp"
#include "locus/pipelines/voronoi/restricted_dual.hpp"
#include "locus/run_context.hpp"

namespace locus {

struct RemeshOptions {
  LloydOptions lloyd;
  int max_repair_rounds = 12;
  int relax_iterations = 0;
  // Midpoint subdivisions of the input the repair may fall back to (see above).
  int max_refinements = 3;
  // Lloyd itself runs on a subdivided input while the input has fewer than
  // this many vertices per site (within max_refinements): a cell of a few
  // vertices vanishes or breaks the closed-ball property.
  double min_vertices_per_site = 12;
  // Passes that bring the remesh's vertex count within 1.5% of lloyd.sites
  // (repair sites and empty cells move it off): sites dropped or split, then
  // density_iterations Lloyd iterations and the repair again (cvt_remesh.cpp
  // meet_density). 0 = the count as it comes.
  int density_passes = 4;
  int density_iterations = 2;
  // Flip + smoothing rounds on the dual (remesh_optimize.hpp); 0 = the dual as is.
  int optimize_rounds = RemeshOptimizeOptions{}.rounds;
  // Feature edges: dihedral angle above this many degrees, in [0, 180);
  // 0 = no features (remesh_features.hpp).
  double feature_angle_deg = 0;
  // RemeshResult::hausdorff_rel of the final remesh (remesh_quality.hpp),
  // through the optimization's grid of the input (no second one).
  bool hausdorff = false;
  // Called once the cells' operator (lloyd.prepared) is solved with no more:
  // after the repair, before the assembly and the optimization. A caller that
  // owns the operator frees it there (its factor ~160 MB at 416k vertices).
  std::function<void()> operator_done;
  // Called once the first Lloyd run is over, before anything reads the
  // derived data's edge incidence: until then the remesh reads of `d` its
  // checks, h, masses, components and vertex adjacency only (Lloyd's cell
  // graph is built on the adjacency). A caller that freed d.incidence
  // meanwhile restores it there (the cvt command's, 25 MB at 416k vertices).
  std::function<void()> lloyd_done;
  // Called before the remesh first reads m.face_vertices: a refinement
  // subdividing the input (max_refinements, before Lloyd or in the repair),
  // the geodesic repair, a density pass, the features, or else right after
  // operator_done (the assembly). Until then it reads m's faces through
  // f0/f1/f2 (Lloyd, the restricted dual, the repair's rounds). A caller
  // that freed them restores them (the cvt command's, 10 MB at 416k vertices).
  std::function<void()> corners_needed;
};

struct RemeshResult {
  LloydResult lloyd;              // the final sites and their labels (the last round's run)
  Mesh remesh;                    // the dual; no faces when defects remain
  std::vector<int32_t> vertex_site;  // per remesh vertex: its site
  bool complete = false;          // no defects left: remesh is the manifold dual
  // Sites beyond the request, net: lloyd.sites holds requested + added_sites
  // (negative when the density passes dropped more than the repair added).
  int32_t added_sites = 0;
  int32_t repair_sites = 0;          // added by the repair rounds, all passes
  // Dropped by the density passes (empty cells included) less the sites they
  // put into split cells: lloyd.sites holds requested + repair_sites - removed_sites.
  int32_t removed_sites = 0;
  int32_t requested = 0;             // lloyd.sites
  int32_t delivered = 0;             // remesh vertices (0 without a manifold remesh)
  int32_t density_passes = 0;        // see RemeshOptions::density_passes
  int32_t repair_rounds = 0;       // all levels
  int32_t refinements = 0;         // subdivisions the repair needed (0: the input's own vertices)
  // Rounds on graph-geodesic labels, after heat labels kept failing (0: none
  // needed); see cvt_remesh.cpp geodesic_repair.
  int32_t geodesic_rounds = 0;
  // Rounds that moved vertices from flat, wide regions to thin ones
  // (remesh_rebalance.hpp; 0 on a remesh at the angle targets).
  int32_t rebalance_rounds = 0;
  // Components of one triangle remeshed as their input triangle
  // (remesh_small_components.hpp: its angles are the input's).
  int32_t single_triangles = 0;
  int32_t lloyd_iterations = 0;   // all rounds
  DualDefects first_defects;      // of the partition after the first Lloyd run
  DualDefects defects;            // left after the last round (all zero when complete)
  double factor_s = 0;            // the shared operator (0 when prepared by the caller)
  double lloyd_s = 0;             // the first Lloyd run
  double repair_s = 0;            // repair rounds (their Lloyd iterations and labels)
  double dual_s = 0;              // defect checks and the dual mesh, all rounds
  // The dual before optimization: mean and min over triangles of the smallest angle.
  double dual_mean_min_angle_deg = 0, dual_min_angle_deg = 0;
  // With feature_angle_deg: the input's feature edges, curves and corners,
  // and the sites placed on them (the first feature_sites of lloyd.sites).
  int64_t feature_edges = 0;
  int32_t feature_curves = 0, feature_corners = 0, feature_sites = 0;
  std::vector<FeatureCurve> feature_lines;  // the curves and their sites, in order along each
  RemeshOptimizeStats optimize;
  double optimize_s = 0;          // the input's triangle grid, flips and smoothing
  double hausdorff_rel = -1;      // with RemeshOptions::hausdorff and a complete remesh, else -1
  double hausdorff_s = 0;
};

RemeshResult cvt_remesh(const Mesh& m, const MeshDerived& d, const RemeshOptions& o, const RunContext& ctx);

}  // namespace locus
