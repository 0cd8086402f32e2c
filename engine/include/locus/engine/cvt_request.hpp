// The request and report of the `cvt` command: a centroidal Voronoi
// tessellation by Lloyd's method with heat cells and centroids (thesis
// §3.7.1), localized (approximate selective solves) or with full solves,
// isotropic or anisotropic, and the remesh: the restricted-Delaunay dual of
// the final cells, repaired into a manifold with the input's topology and
// optimized on the surface. As every front end runs it: the CLI (`locus cvt`),
// locus::Session::cvt(const CvtRequest&), the C API (locus_cvt_options in
// locus_commands.h) and Python (Session.cvt_command). Each field is one
// option, named as the CLI's long option ('-' as '_'), with the CLI's
// default; the checks and the call sequence live once, in
// engine/src/session_cvt_command.cpp. Session::cvt(sites, iterations, seed)
// stays the cached tier (the cells' operator kept by the Session).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "locus/engine/geodesic_requests.hpp"
#include "locus/export.h"
#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API CvtRequest {
  int32_t sites = 100;          // seeded random initial sites, one per component at least; more than the
                                // vertices: the cells run on a midpoint subdivision of the mesh
  int32_t iters = 10;           // Lloyd iterations, 0..1000000
  double stop_energy = 0.0;     // [0, 1]: stop once an iteration lowers the energy by less than this fraction
  double anisotropy = 0.0;      // lambda of the R^6 lift (p, lambda n), 0..1e6; 0 = isotropic (thesis: 0.05)
  std::string solver = "local"; // local (approximate selective solves) or full
  std::string t = "4h2";        // the cells' diffusion time: absolute or a multiple of h^2 (thesis: h2)
  std::string save, load;       // factor cache files of the cells' M - tL (isotropic only; "" = none)
  bool no_refine = false;       // centroids at the hottest vertex (no quadratic fit)
  std::string centroid_t;       // the centroids' time, as t; "" = the cells' t
  std::string t_centroid;       // deprecated spelling of centroid_t: C means "Ch2" (0: the cells' t); "" = not given
  int32_t fit_rings = 2;        // 1..4 vertex rings of the centroid's quadratic fit (the thesis fits 1)
  double fit_sigma = 1.0;       // 0..100: weighted refit of the maximizer, in one-ring distances (0 = none)
  bool no_split = false;        // cell sources from vertex labels only (no split triangles)
  std::string labels;           // write the input with a per-vertex `label` property (ply, obj, off; "" = none)
  std::string sites_out;        // write the final sites as points (ply keeps face and barycentrics; "" = none)
  int32_t repair_rounds = 12;   // 0..1000 rounds of added sites that make the remesh a manifold
  int32_t refinements = 3;      // 0..4 midpoint subdivisions the repair may use
  int32_t optimize = 6;         // 0..100 rounds of flips and tangential smoothing of the remesh
  // Sharp features kept by the remesh: input edges whose dihedral angle (between
  // their faces' normals) exceeds this many degrees, in [0, 180); 0 = none.
  double features = 0.0;
  bool no_hausdorff = false;    // skip the remesh's Hausdorff distance (hausdorff_rel -1)
  bool track_quality = false;   // record the dual angles of every iteration (mean_angle_all, min_angle_all)
  uint64_t seed = 1;            // of the initial sites (the CLI's --seed)
};

// What blocks the closed-ball property of the cells (the remesh's repair).
struct LOCUS_API CvtDefects {
  int64_t split_cells = 0, non_disk_cells = 0, split_interfaces = 0, loop_interfaces = 0,
          boundary_interfaces = 0, repeated_corners = 0, split_boundary_runs = 0, short_boundary_loops = 0;
};

// Topology and triangle quality of a mesh (the remesh, or the input's topology).
struct LOCUS_API CvtMeshStats {
  int32_t vertices = 0, faces = 0;
  bool manifold = false;
  int64_t genus = -1;                 // summed over components; -1 when not manifold
  int32_t components = 0, boundary_loops = 0;
  double mean_min_angle_deg = 0, min_angle_deg = 0, pct_below_30_deg = 0;  // per triangle's smallest angle
  double hausdorff_rel = -1;          // to the input, of its bounding-box diagonal; -1 when not computed
};

// How a mesh that is not a manifold (non-manifold edges or vertices,
// zero-area or repeated faces, inconsistent orientation, unreferenced
// vertices) was cut into the manifold sheets the cells and the remesh run on
// (kernels/.../manifold_sheets.hpp, docs/robust_operator.md); all zero when
// the mesh is used as it is.
struct LOCUS_API CvtSheets {
  bool cut = false;
  int64_t split_vertices = 0, cut_edges = 0, flipped_faces = 0, dropped_faces = 0, split_faces = 0,
          unreferenced_vertices = 0;
};

struct LOCUS_API CvtReport {
  // The cells: per vertex its site; the sites (the repair's added ones too).
  std::vector<int32_t> label;
  std::vector<double> site_xyz;       // 3 per site
  std::vector<int32_t> site_face;     // per site: the triangle holding it, -1 on a vertex
  std::vector<int32_t> site_vertex;   // per site: that vertex, or -1
  std::vector<double> site_bary;      // 3 per site: weights in site_face
  // The remesh: the manifold dual when `complete` (no faces otherwise).
  bool complete = false;
  Mesh remesh;
  std::vector<int32_t> remesh_site;   // per remesh vertex: its site
  CvtMeshStats remesh_stats;          // all zero (genus -1) without a complete remesh
  CvtMeshStats input_stats;           // the input's topology (genus, components, boundary loops)
  int32_t added_sites = 0, repair_rounds = 0, refinements = 0, lloyd_iterations = 0;
  // The requested density (sites) against the delivered remesh vertices: the
  // repair's added sites, the density passes' removed ones, and how many
  // passes and shortest-path repair rounds (the repair's last resort) ran.
  int32_t requested = 0, delivered = 0, repair_sites = 0, removed_sites = 0, density_passes = 0,
          geodesic_rounds = 0;
  // Rounds that moved vertices from flat, wide regions to thin ones, and
  // components of one triangle given their input triangle (cvt_remesh.hpp).
  int32_t rebalance_rounds = 0, single_triangles = 0;
  double dual_mean_min_angle_deg = 0, dual_min_angle_deg = 0;  // before the optimization
  int64_t flips = 0, smoothing_moves = 0, boundary_moves = 0;
  // With features: the input's feature edges, curves and corners, and the
  // sites placed on them (their remesh vertices stay on the creases).
  int64_t feature_edges = 0;
  int32_t feature_curves = 0, feature_corners = 0, feature_sites = 0;
  CvtDefects defects_before_repair, defects_left;
  // Lloyd (the last round's run).
  int32_t n = 0;                      // vertices
  double h = 0, t = 0, t_centroid = 0;
  int64_t factor_bytes = 0;
  double mean_kept_fraction = 0;
  int64_t fallback_faces = 0, unreached = 0;
  int64_t lloyd_empty_cells = 0;     // cells without vertices, over all iterations (their sites stayed)
  std::vector<double> cell_area;      // cells with triangles split along the bisectors
  double area_cv = 0, area_variance = 0;
  std::vector<double> energy, moved, centroid_bias, centroid_bias_median;
  std::vector<double> mean_angle, min_angle;  // with track_quality: per iteration
  // Quality of the cells' dual triangles and of the vertex-star cells.
  int64_t dual_triangles = 0;
  double cells_min_angle_deg = 0, cells_mean_angle_deg = 0;
  std::array<int32_t, 3> min_angle_sites{{-1, -1, -1}};
  std::array<int64_t, 12> angle_histogram{};  // dual triangles per 5-degree bin of the smallest angle
  double area_cv_vertex = 0, area_variance_vertex = 0;
  int64_t empty_cells = 0;
  // Seconds: the cells' operator (factored or loaded by the command), Lloyd's
  // phases, the remesh's and the statistics.
  double prepare_s = 0, init_s = 0, lloyd_factor_s = 0, final_labels_s = 0;
  std::vector<double> iter_s;
  double labels_s = 0, partition_s = 0, neighbourhoods_s = 0, centroids_s = 0;
  double remesh_factor_s = 0, lloyd_s = 0, repair_s = 0, dual_s = 0, optimize_s = 0, stats_s = 0;
  FactorCacheReport factor_cache;
  CvtSheets sheets;                   // the input's labels and sites are mapped back from the sheets
};

// Argument checks that need no mesh, the output targets included: Error(BadUsage).
LOCUS_API void check_request(const CvtRequest& req);

// Writes the files the request names ("" = none): `labels`, the mesh `faces`
// (on the vertices the command worked on) with the per-vertex property
// `label` added to `carried` (the host file's own vertex properties, or
// none); `sites_out`, the final sites as points with the properties face,
// vertex (-1 off a vertex), b0, b1, b2 and, with `triangle_polygon` (per
// triangle its polygon in a triangulated polygon file; empty otherwise),
// polygon. Session::cvt writes them with its own faces; the CLI with the
// file's faces and vertex attributes.
LOCUS_API void write_cvt_files(const CvtRequest& req, const CvtReport& r, const Mesh& faces, WriteOptions carried,
                               const std::vector<int32_t>& triangle_polygon);

}  // namespace locus
LOCUS_API_END
