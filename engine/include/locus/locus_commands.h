/* The commands of the `locus` CLI with every option, for C hosts: one
 * options struct per command (each field the CLI's option of the same name,
 * '-' as '_', with its default from locus_<command>_options_default()), one
 * locus_<command>_run call, the numbers of the CLI bit for bit. Part of
 * locus.h, which includes it (the geodesic and logmap commands are there).
 * The same conventions as locus.h: NULL or "" strings mean the default,
 * status codes, locus_last_error_message(); a call may run concurrently with
 * other calls on the same session. The engine's requests behind them:
 * engine/include/locus/engine/<area>_request(s).hpp. */
#ifndef LOCUS_LOCUS_COMMANDS_H
#define LOCUS_LOCUS_COMMANDS_H

#include "locus/locus.h"

#ifdef __cplusplus
extern "C" {
#endif
LOCUS_API_BEGIN

/* ---- The adf, hks and heat commands, every option of `locus adf`, `locus hks`
 * and `locus heat` (engine/include/locus/engine/diffusion_requests.hpp) ----
 * As the geodesic command's options above: each field is the CLI's option of
 * the same name with its default (locus_*_options_default()); NULL or "" strings
 * mean the default. Times are text ("1h2": a multiple of h^2; "0.001": absolute).
 * Vertex lists are arrays with their counts. Each call factors M - tL for its
 * times itself (one ordering for every t), or loads the factors from `load`
 * (refused with LOCUS_BAD_INPUT when made for another mesh or t) and with
 * `save` writes them. opts->t_factor must be 0 here. */
typedef struct locus_adf_options {
  const char* t;             /* NULL: "1h2" */
  const int64_t* vertices;   /* the vertices to evaluate ... */
  int64_t n_vertices;
  int32_t all;               /* ... or nonzero: every vertex (exactly one of the two) */
  const char* method;        /* "subset" (default), "selinv" or "full" */
  const char* save;          /* NULL: none */
  const char* load;          /* NULL: none */
} locus_adf_options;
LOCUS_API locus_adf_options locus_adf_options_default(void);

typedef struct locus_hks_options {
  const char* const* ts;     /* n_ts times, in the order of the output */
  int64_t n_ts;
  const int64_t* vertices;
  int64_t n_vertices;
  int32_t all;
  const char* method;
  const char* save;
  const char* load;
} locus_hks_options;
LOCUS_API locus_hks_options locus_hks_options_default(void);

/* What an adf or hks run reports beside the values (as `locus adf|hks --json`). */
typedef struct locus_signature_report {
  int64_t evaluated;         /* vertices evaluated (n_vertices, or the vertex count with all) */
  double h;                  /* mean edge length */
  int64_t nnz_L;
  int32_t supernodes, etree_height;
  double operator_s, order_s, analyze_s, numeric_s, query_s;
} locus_signature_report;

/* out: evaluated * (number of times) doubles, out[k * n_times + j] the value at
 * the k-th evaluated vertex for the j-th time; out_t (may be NULL): the times
 * used, absolute; out_report may be NULL. The numbers are the CLI's, bit for bit. */
LOCUS_API locus_status locus_adf_run(locus_session* session, const locus_adf_options* options, double* out,
                                     double* out_t,
                                     locus_signature_report* out_report, const locus_run_options* opts);
LOCUS_API locus_status locus_hks_run(locus_session* session, const locus_hks_options* options, double* out,
                                     double* out_t,
                                     locus_signature_report* out_report, const locus_run_options* opts);

typedef struct locus_heat_options {
  const int64_t* source;     /* unit heat at each (repeats add), at least one */
  int64_t n_source;
  const int64_t* target;     /* at least one */
  int64_t n_target;
  const char* t;             /* NULL: "1h2" */
  const char* method;        /* "subset" (default), "union" or "full" */
  int32_t repeat;            /* 1..100000, default 1: the query's repeats (median timings) */
  const char* save;
  const char* load;
} locus_heat_options;
LOCUS_API locus_heat_options locus_heat_options_default(void);

typedef struct locus_heat_report {
  double t, h, total;        /* the time used, the mean edge length, the sum of the values */
  int64_t nnz_L;
  int32_t etree_height;
  int64_t forward_columns, backward_columns;
  double operator_s, order_s, analyze_s, numeric_s, query_s, plan_s, solve_s;
} locus_heat_report;

/* out_targets: n_target doubles, the heat at each target; out_report may be NULL. */
LOCUS_API locus_status locus_heat_run(locus_session* session, const locus_heat_options* options, double* out_targets,
                                      locus_heat_report* out_report, const locus_run_options* opts);

/* The deform command, every option of `locus deform` (engine/include/locus/
 * engine/deform_request.hpp), as the geodesic command's options above:
 * locus_deform_options_default() gives the CLI's defaults; NULL or "" strings
 * the default. The global factor at the default regularization is the
 * session's (kept); another regularization or save/load factors (or loads)
 * its own for the call. out_xyz: 3 * vertex-count doubles; out_report may be
 * NULL. The positions are `locus deform`'s, bit for bit. */
typedef struct locus_deform_options {
  int64_t roi_seed;        /* required (default -1) */
  double roi_fraction;     /* [0, 1], default 0.1 */
  int64_t handle;          /* required (default -1), inside the ROI */
  int32_t handle_ring;     /* 0..1000, default 1 */
  double offset[3];        /* the handle's displacement */
  const char* energy;      /* "laplacian" (default) or "bilaplacian" */
  double regularization;   /* > 0, default 1e-6 */
  const char* save;        /* NULL: none */
  const char* load;        /* NULL: none */
} locus_deform_options;
LOCUS_API locus_deform_options locus_deform_options_default(void);

typedef struct locus_deform_report {
  int32_t roi_vertices, handle_vertices, free_vertices;
  double columns_updated_fraction;
  int32_t refinement_steps;
  double residual, max_displacement;
  double global_factor_s, update_s, solve_s;
} locus_deform_report;
LOCUS_API locus_status locus_deform_run(locus_session* session, const locus_deform_options* options, double* out_xyz,
                                        locus_deform_report* out_report, const locus_run_options* opts);

/* The param command, every option of `locus param` (engine/include/locus/
 * engine/param_request.hpp), as the geodesic command's options above. center
 * < 0: the disk (methods perfect, cotan, uniform); center >= 0: the patch of
 * round(fraction * nv) vertices (boundary "neumann" or "circle", save/load of
 * the global factor). out_uv: 2 * vertex-count doubles, NaN outside the patch;
 * out_report may be NULL. The numbers are `locus param`'s, bit for bit. */
typedef struct locus_param_options {
  const char* method;     /* disk: "perfect" (default), "cotan" or "uniform" */
  int32_t iters;          /* disk, perfect: iteration cap, default 1000 */
  double eps;             /* disk, perfect: tolerance, default 1e-6 */
  int64_t center;         /* -1 (default): the disk; else the patch around this vertex */
  double fraction;        /* patch: (0, 1], default 0.1 */
  const char* boundary;   /* patch: "neumann" (default) or "circle" */
  const char* save;       /* patch: NULL: none */
  const char* load;
} locus_param_options;
LOCUS_API locus_param_options locus_param_options_default(void);
typedef struct locus_param_report {
  int64_t patch_size;     /* vertices with a value (the vertex count for the disk) */
  int64_t flipped_faces, degenerate_faces, negative_weights;
  int32_t boundary_vertices, converged, iterations;
  double query_s;
} locus_param_report;
LOCUS_API locus_status locus_param_run(locus_session* session, const locus_param_options* options, double* out_uv,
                                       locus_param_report* out_report, const locus_run_options* opts);

/* The perfect-laplacian and selfsupport commands, every option of `locus
 * perfect-laplacian` and `locus selfsupport` (engine/include/locus/engine/
 * laplacian_requests.hpp), as the geodesic command's options above; outputs
 * as locus_perfect_laplacian / locus_self_supporting (any may be NULL). The
 * numbers are the CLI's, bit for bit. */
typedef struct locus_perfect_laplacian_options {
  int32_t planar;          /* nonzero: use x, y (one boundary loop) */
  int32_t iters;           /* 1..1000000, default 1000 */
  double eps;              /* default 1e-6 */
  const char* method;      /* "newton" (default) or "multiplicative" */
  int32_t anderson;        /* multiplicative: 0..50, default 6 */
  int32_t no_active_set;   /* nonzero: keep iterating every weight */
  double noise;            /* >= 0: seeded noise of up to noise * h per coordinate first (default 0) */
  uint64_t seed;           /* of the noise, default 1 */
} locus_perfect_laplacian_options;
LOCUS_API locus_perfect_laplacian_options locus_perfect_laplacian_options_default(void);
LOCUS_API locus_status locus_perfect_laplacian_run(locus_session* session,
                                                   const locus_perfect_laplacian_options* options,
                                                   int32_t* out_edges, double* out_weights, double* out_xyz,
                                                   int32_t* out_converged, const locus_run_options* opts);

typedef struct locus_selfsupport_options {
  const char* support;     /* "boundary" (default, the only choice) */
  double load_density;     /* > 0, default 1 */
  int32_t iters;           /* default 1000 */
  double eps;              /* default 1e-6 */
} locus_selfsupport_options;
LOCUS_API locus_selfsupport_options locus_selfsupport_options_default(void);
LOCUS_API locus_status locus_selfsupport_run(locus_session* session, const locus_selfsupport_options* options,
                                             int32_t* out_edges, double* out_forces, double* out_xyz,
                                             int32_t* out_converged,
                                             const locus_run_options* opts);

/* The nncoords command, every option of `locus nncoords` (engine/include/
 * locus/engine/nncoords_request.hpp): out_weights receives n_sites doubles
 * (in sites order); out_report may be NULL. The numbers are the CLI's, bit
 * for bit; locus_nncoords_prepare above serves many points. */
typedef struct locus_nncoords_options {
  const int64_t* sites;   /* vertex ids, at least one */
  int64_t n_sites;
  locus_surface_point point;  /* a point in a face (face >= 0) */
  const char* t;          /* NULL: "h2" */
} locus_nncoords_options;
LOCUS_API locus_nncoords_options locus_nncoords_options_default(void);
typedef struct locus_nncoords_report {
  double cell_area, clamped, t;
  int32_t at_site, degenerate;
  int64_t fallback_faces;
  double prepare_s, query_s;
} locus_nncoords_report;
LOCUS_API locus_status locus_nncoords_run(locus_session* session, const locus_nncoords_options* options,
                                          double* out_weights,
                                          locus_nncoords_report* out_report, const locus_run_options* opts);

/* The skinweights command, every option of `locus skinweights`
 * (engine/include/locus/engine/skinning_requests.hpp): handles as vertex sets and bones, the sampled method
 * (default; on a coarse level of a mesh with more than 48,000 vertices) or the exact per-vertex one. Handle i's vertices are
 * handles[handle_offsets[i] .. handle_offsets[i+1]) (handle_offsets NULL:
 * one vertex per handle); bone b is the polyline of points
 * bone[3 * bone_offsets[b] .. 3 * bone_offsets[b+1]) (x, y, z each, >= 2
 * points) and comes after the handles. out: vertex-count * (n_handles + n_bones)
 * doubles, row-major. out_report may be NULL. Same numbers as the CLI. */
typedef struct locus_skinweights_options {
  const int64_t* handles;
  const int64_t* handle_offsets; /* n_handles + 1 entries, or NULL */
  int64_t n_handles;
  const double* bone;
  const int64_t* bone_offsets;   /* n_bones + 1 entries (point counts) */
  int64_t n_bones;
  int32_t exact;                 /* nonzero: natural-neighbor coordinates at every vertex (slow) */
  int32_t samples;               /* sampled method: at most this many exact rows; 0 = 1024 */
  const char* t;                 /* NULL: h2 */
} locus_skinweights_options;
LOCUS_API locus_skinweights_options locus_skinweights_options_default(void);

typedef struct locus_skinweights_report {
  int64_t handles;
  int32_t exact;        /* 1 when the exact method ran */
  int32_t samples;      /* vertices whose row is exact */
  int32_t sample_rings; /* sampled: every vertex within this many edges of a sample */
  double radius;        /* sampled: propagation radius */
  double t;
  int64_t degenerate_vertices;
  double factor_s, prepare_s, weights_s, propagate_s;
} locus_skinweights_report;

LOCUS_API locus_status locus_skinweights_run(locus_session* session, const locus_skinweights_options* options,
                                          double* out, locus_skinweights_report* out_report,
                                          const locus_run_options* opts);

/* The voronoi command, every option of `locus voronoi` (engine/include/locus/
 * engine/voronoi_request.hpp), as the geodesic command's options above:
 * generators are the vertex `sites` or `random` seeded random surface points
 * (exactly one). out_labels: vertex-count int32 (the generator with the most
 * heat); out_report may be NULL. The labels are `locus voronoi`'s, bit for bit. */
typedef struct locus_voronoi_options {
  const int64_t* sites;  /* vertex ids ... */
  int64_t n_sites;
  int32_t random;        /* ... or this many random points (0: not given) */
  const char* t;         /* NULL: "h2" */
  const char* save;      /* NULL: none */
  const char* load;      /* NULL: none */
  uint64_t seed;         /* of random, default 1 */
} locus_voronoi_options;
LOCUS_API locus_voronoi_options locus_voronoi_options_default(void);
typedef struct locus_voronoi_report {
  int64_t generators, points, segments, polylines, corners, empty_cells, vertices_without_heat;
  double h, t;
} locus_voronoi_report;
LOCUS_API locus_status locus_voronoi_run(locus_session* session, const locus_voronoi_options* options,
                                         int32_t* out_labels,
                                         locus_voronoi_report* out_report, const locus_run_options* opts);

/* The factor command, every option of `locus factor` (engine/include/locus/
 * engine/factor_request.hpp), as the geodesic command's options above: the
 * cotan heat operator M - tL or regularized Laplacian -L + eps M of the
 * session's mesh ordered, analyzed, factored (or loaded from `load`, written
 * to `save`) and solved for a seeded random right-hand side, `repeat` times;
 * the report gives the factor's sizes, the medians of the phases' seconds
 * and the residuals (LOCUS_NUMERICAL when the solve is inaccurate).
 * out_x: vertex-count doubles, the last repeat's 1-lane solution (NULL: not
 * wanted); out_report may be NULL. opts->t_factor must be 0. The numbers are
 * `locus factor`'s, bit for bit. */
typedef struct locus_factor_options {
  const char* matrix;        /* NULL: "heat" (M - tL); or "laplacian" (-L + eps M) */
  const char* t;             /* heat only; NULL: "h2" (a multiple of h^2, or absolute) */
  int32_t repeat;            /* 1..1000 runs, default 1; the report gives medians */
  const char* save;          /* NULL: none */
  const char* load;          /* NULL: none */
  uint64_t seed;             /* of the right-hand side, default 1 */
} locus_factor_options;
LOCUS_API locus_factor_options locus_factor_options_default(void);
typedef struct locus_factor_report {
  int32_t n, repeats;
  int64_t nnz_A, nnz_L, nnz_L_exact;
  int32_t supernodes, etree_height, super_etree_height;
  int64_t flops;
  double t, h;               /* t: 0 for the Laplacian */
  double residual, residual8, lane0_vs_solve;
  double operator_s, order_s, symbolic_s, numeric_s, solve_s, solve8_s, load_s, save_s;
} locus_factor_report;
LOCUS_API locus_status locus_factor_run(locus_session* session, const locus_factor_options* options, double* out_x,
                                        locus_factor_report* out_report, const locus_run_options* opts);

/* The info command, `locus info` (engine/include/locus/engine/mesh_info.hpp):
 * sizes, topology and defects of the session's mesh as given (its polygons for
 * a polygon mesh), with its current positions. Faces by degree: triangles,
 * quads and larger. genus -1: undefined (not a connected manifold); the first
 * offender of each kind -1 when none. The numbers of `locus info --json`. */
typedef struct locus_info_report {
  int64_t n_vertices, n_faces, n_edges;
  int64_t triangles, quads, larger_faces;
  int64_t components, boundary_loops, euler_characteristic, genus;
  int32_t manifold;
  int64_t non_manifold_edges, non_manifold_vertices, degenerate_faces, unreferenced_vertices;
  double bbox_min[3], bbox_max[3];
  double mean_edge_length;
  int64_t first_non_manifold_edge_v0, first_non_manifold_edge_v1, first_non_manifold_vertex;
  int64_t first_degenerate_face, first_unreferenced_vertex;
} locus_info_report;
LOCUS_API locus_status locus_info_run(const locus_session* session, locus_info_report* out);

/* The cvt command, every option of `locus cvt` (engine/include/locus/engine/
 * cvt_request.hpp), as the geodesic command's options above:
 * locus_cvt_options_default() gives the CLI's defaults; NULL or "" strings
 * the default (centroid_t and t_centroid: not given). The cells' operator
 * M - tL is factored by the call (or loaded from `load`, written to `save`;
 * isotropic only); labels and sites_out name files the call writes (the
 * session's mesh with a per-vertex `label` property; the sites as points
 * with face, vertex and barycentric properties), checked before any work.
 * out_labels: vertex-count int32, each vertex's site (NULL: not wanted);
 * out_report may be NULL; out_remesh (may be NULL) receives a handle to free
 * with locus_remesh_destroy: the remesh (no vertices when report.complete is
 * 0: the cells still break the closed-ball property after the repair rounds)
 * and the final sites (locus_remesh_get_sites). opts->t_factor must be 0.
 * The labels, remesh and sites are `locus cvt`'s, bit for bit. */
typedef struct locus_cvt_options {
  int32_t sites;             /* at least one per component (more than the vertices: a subdivision); default 100 */
  int32_t iters;             /* 0..1000000, default 10 */
  double stop_energy;        /* [0, 1], default 0: all iters */
  double anisotropy;         /* lambda of the R^6 lift, 0..1e6; default 0: isotropic */
  const char* solver;        /* "local" (default) or "full" */
  const char* t;             /* NULL: "4h2" */
  const char* save;          /* NULL: none */
  const char* load;          /* NULL: none */
  int32_t no_refine;         /* nonzero: centroids at the hottest vertex */
  const char* centroid_t;    /* NULL: the cells' t */
  const char* t_centroid;    /* deprecated: "C" is centroid_t "Ch2"; NULL: not given */
  int32_t fit_rings;         /* 1..4, default 2 */
  double fit_sigma;          /* 0..100, default 1 */
  int32_t no_split;          /* nonzero: cell sources from vertex labels only */
  const char* labels;        /* NULL: none */
  const char* sites_out;     /* NULL: none */
  int32_t repair_rounds;     /* 0..1000, default 12 */
  int32_t refinements;       /* 0..4, default 3 */
  int32_t optimize;          /* 0..100, default 6 */
  int32_t no_hausdorff;      /* nonzero: remesh.hausdorff_rel -1 */
  int32_t track_quality;     /* unused by the C report (the CLI's per-iteration JSON) */
  uint64_t seed;             /* of the initial sites, default 1 */
  double features;           /* dihedral angle in degrees, [0, 180): sharper input edges stay remesh edges; default 0: none */
} locus_cvt_options;
LOCUS_API locus_cvt_options locus_cvt_options_default(void);
typedef struct locus_cvt_report {
  int64_t sites;             /* final sites, the repair's added ones included */
  int32_t complete;          /* 1 when the remesh is the manifold dual */
  int32_t added_sites, repair_rounds, refinements, lloyd_iterations;
  locus_remesh_stats remesh; /* zero (genus -1) without a complete remesh */
  double h, t, t_centroid;
  int64_t dual_triangles;
  double min_angle_deg, mean_angle_deg;  /* smallest angles of the cells' dual triangles */
  double area_cv, area_variance, area_cv_vertex, area_variance_vertex;
  int64_t empty_cells, unreached_vertices, fallback_faces;
  int64_t flips, smoothing_moves, boundary_moves;
  int64_t defects_left;      /* summed over the kinds (0 when complete) */
  /* requested sites against delivered remesh vertices; sites the repair added
   * and the density passes removed; passes and shortest-path repair rounds run */
  int32_t requested, delivered, repair_sites, removed_sites, density_passes, geodesic_rounds;
  /* with features: the input's feature edges, curves and corners, and the sites placed on them */
  int64_t feature_edges;
  int32_t feature_curves, feature_corners, feature_sites;
  /* rounds of the rebalance (sites moved from flat to thin parts) kept, and one-triangle components given back their input triangle */
  int32_t rebalance_rounds, single_triangles;
} locus_cvt_report;
LOCUS_API locus_status locus_cvt_run(locus_session* session, const locus_cvt_options* options, int32_t* out_labels,
                                     locus_cvt_report* out_report, locus_remesh** out_remesh,
                                     const locus_run_options* opts);
/* The final sites of a remesh handle (locus_cvt_run or locus_cvt_remesh):
 * out_xyz receives 3 * locus_remesh_num_sites() doubles. */
LOCUS_API int64_t locus_remesh_num_sites(const locus_remesh* remesh);
LOCUS_API locus_status locus_remesh_get_sites(const locus_remesh* remesh, double* out_xyz);

LOCUS_API_END
#ifdef __cplusplus
}
#endif

#endif /* LOCUS_LOCUS_COMMANDS_H */
