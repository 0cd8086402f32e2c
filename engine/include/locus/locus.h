/* locus.h — the C API of locus (README "Embedding").
 *
 * For game engines, DCC plugins and other languages: opaque session handles,
 * flat arrays with counts, outputs written into caller memory, status codes,
 * and no exception or abort ever crosses this boundary. C99 and C++.
 *
 * A session owns one triangle mesh and caches what is derived from it: the
 * first query factors the operators it needs (heat method: M - tL and
 * -L + eps M, t = h^2 with h the mean edge length), every later query reuses
 * those factors. Every pipeline of the `locus` CLI has a call here (the
 * diffusion, deformation and shape calls follow the heat method's), returning
 * the CLI's numbers for the same arguments. See locus/session.hpp for the algorithms.
 *
 * Status codes mirror the exit statuses of the `locus` command-line tool:
 *   LOCUS_OK (0), LOCUS_BAD_USAGE (2: a wrong argument — null pointer, count or
 *   vertex id out of range), LOCUS_BAD_INPUT (3: an unreadable or unsuitable
 *   mesh, or a resource limit such as memory), LOCUS_NUMERICAL (4: an operator
 *   is not positive definite, a result is not finite), LOCUS_CANCELLED (5: a
 *   progress callback asked to stop), LOCUS_INTERNAL (70: a bug in locus).
 * On failure, locus_last_error_message() says what is wrong and where, and
 * output arrays may have been partly written.
 *
 * Thread safety: a session may be queried from any number of threads at once
 * (two threads that need the same factor share one factorization; results are
 * bit-identical to single-threaded calls). locus_session_destroy must not run
 * concurrently with any other call on that session. The last-error message is
 * per thread.
 *
 * Vertex ids are 0-based, in the order of the input.
 */
#ifndef LOCUS_LOCUS_H
#define LOCUS_LOCUS_H

#include <stddef.h>
#include <stdint.h>

#include "locus/export.h"  /* LOCUS_API: what a shared liblocus exports */
#include "locus/version.h" /* LOCUS_VERSION_MAJOR/MINOR/PATCH/STRING, the CMake package version */

#ifdef __cplusplus
extern "C" {
#endif
LOCUS_API_BEGIN

typedef enum locus_status {
  LOCUS_OK = 0,
  LOCUS_BAD_USAGE = 2,
  LOCUS_BAD_INPUT = 3,
  LOCUS_NUMERICAL = 4,
  LOCUS_CANCELLED = 5,
  LOCUS_INTERNAL = 70
} locus_status;

/* Opaque handle. */
typedef struct locus_session locus_session;

/* Progress of a long call: `fraction` in [0, 1] within `phase` (a short
 * English name, valid during the call only). Return 0 to continue, nonzero to
 * cancel: the call then stops at its next check and returns LOCUS_CANCELLED.
 * locus serializes the calls of one operation (never two at once for one
 * call), but they may come from worker threads. */
typedef int (*locus_progress_fn)(double fraction, const char* phase, void* user_data);

/* A diagnostic that is not an error (e.g. "threads = 100000 is more than this
 * process allows (2); using 2"); `text` is valid during the call only. locus
 * never writes to stdout or stderr: without this callback such notes are
 * dropped. Called like the progress callback (serialized, any thread). */
typedef void (*locus_message_fn)(const char* text, void* user_data);

/* Options of a long call; a NULL pointer, or a zero-initialized struct, means
 * all defaults (locus_run_options_default() returns them). */
typedef struct locus_run_options {
  int32_t threads;           /* worker threads, 0 = all cores (default) */
  locus_progress_fn progress; /* NULL: no progress reports, no cancellation */
  void* user_data;           /* passed to progress */
  uint64_t max_memory_bytes; /* limit of one factorization, 0 = 80% of physical memory */
  double t_factor;           /* heat diffusion time t = t_factor * h^2; 0 = the method's default: 4 for geodesic distance
                                and log maps, 1 for the diffusion calls (cvt: default only, its cells use t = 4h^2) */
  locus_message_fn message;  /* NULL: notes are dropped; gets user_data too */
} locus_run_options;

/* The defaults: threads 0, no callbacks, no memory limit beyond the default, t_factor 0 (each method's default). */
LOCUS_API locus_run_options locus_run_options_default(void);

/* Version of the library (which may differ from the LOCUS_VERSION_* macros of
 * the header a program was compiled with; both equal the CMake package
 * version of their build); any pointer may be NULL. Returns "major.minor.patch"
 * (a static string). Thread-safe, never fails. */
LOCUS_API const char* locus_version(int32_t* major, int32_t* minor, int32_t* patch);

/* Message of the last failed call on this thread ("" after a successful call:
 * every function except this one and locus_last_error_copy clears it on
 * entry). Never NULL. The pointer is this thread's message buffer: it stays
 * valid until the thread exits, but its content changes at the next locus call
 * on this thread, so read it after the failed call and before the next one
 * (not as an argument beside that call: C leaves the order of evaluation open).
 * Messages longer than 4095 bytes are cut; locus_last_error_copy has them whole. */
LOCUS_API const char* locus_last_error_message(void);

/* Copies the message of the last failed call on this thread into `buffer`
 * (`capacity` bytes; cut to capacity - 1 bytes and NUL-terminated when
 * capacity >= 1; nothing is written when buffer is NULL or capacity <= 0) and
 * returns the message's whole length in bytes, without the NUL:
 * locus_last_error_copy(NULL, 0) + 1 bytes hold it. Does not clear the message.
 * Thread-safe; never fails. */
LOCUS_API int64_t locus_last_error_copy(char* buffer, int64_t capacity);

/* ---- The host's allocator (README "Embedding: the allocator") ----
 * Routes locus' large buffers through the host's memory: alloc(size, user_data)
 * returns `size` bytes aligned to 16 bytes (as malloc does), or NULL when it
 * has none (the call in progress then fails with LOCUS_BAD_INPUT, "out of
 * memory"); free_fn(ptr, user_data) releases a block alloc returned. Both
 * callbacks, or both NULL (back to the C library's malloc/free); otherwise
 * LOCUS_BAD_USAGE. They may be called from any thread, concurrently (locus'
 * worker threads allocate too), and must not call locus.
 * What goes through them: numeric factor values (the largest buffers by far),
 * the factorization's and the solves' workspaces, the heat batches and heat
 * Voronoi buffers of the diffusion pipelines and the CVT, selected-inversion
 * blocks, the factor-once update's arrays, and every allocation METIS makes
 * inside the orderings. What does not: the mesh and its derived arrays, the
 * operators, orderings, symbolic structures, results (C++ containers),
 * oneTBB's task storage, and OpenBLAS' buffers (allocated once per process by
 * OpenBLAS itself). docs/shipping.md has the shares measured on armadillo
 * (a first geodesic 25% of the bytes in blocks >= 64 KB, a CVT 53%).
 * Every block remembers the callbacks that allocated it and is freed by them,
 * so the allocator may be changed at any time, even while sessions hold
 * cached factors; blocks are freed at the latest when the session, result
 * handle or nncoords field holding them is destroyed. Thread-safe. */
typedef void* (*locus_alloc_fn)(size_t size, void* user_data);
typedef void (*locus_free_fn)(void* ptr, void* user_data);
LOCUS_API locus_status locus_set_allocator(locus_alloc_fn alloc, locus_free_fn free_fn, void* user_data);

/* Reads a mesh file (.off, .obj, .ply by extension) into a new session.
 * Polygon faces: as locus_session_create_polygons.
 * The mesh needs at least one face and finite coordinates; with the default
 * operator (AUTO, below) any triangle soup is taken; with COTAN it must be a
 * manifold triangle mesh without zero-area faces or unreferenced vertices
 * (boundaries are fine); otherwise LOCUS_BAD_INPUT naming the file and the element.
 * path: NUL-terminated. out: receives the handle (set to NULL on failure).
 * Builds no operator (queries factor on first use). Thread-safe. */
LOCUS_API locus_status locus_session_create_from_file(const char* path, locus_session** out);

/* The Laplacian a session runs on (locus/engine/operator_choice.hpp), one
 * name and default in every front end (CLI --operator, Python operator=):
 * AUTO (the default of every call without options): the cotan operator on a
 * clean manifold mesh, results bit for bit those of COTAN; the robust operator
 * (intrinsic Delaunay triangulation of the tufted cover, Sharp & Crane 2020)
 * when the mesh has a non-manifold edge or vertex, a zero-area or needle face,
 * inconsistent orientation or unreferenced vertices. COTAN refuses such meshes
 * (LOCUS_BAD_INPUT naming the element). ROBUST: always the robust operator.
 * On the robust operator geodesic distance, heat values and the diffusion
 * calls answer (unreferenced vertices: NaN distances); locus_logmap refuses. */
typedef enum locus_operator {
  LOCUS_OPERATOR_AUTO = 0,
  LOCUS_OPERATOR_COTAN = 1,
  LOCUS_OPERATOR_ROBUST = 2
} locus_operator;
typedef struct locus_session_options {
  int32_t mesh_operator; /* locus_operator; 0 = AUTO */
  int32_t no_weld;       /* files read through assimp (glTF, FBX, ...): 1 keeps the file's vertices */
} locus_session_options;

/* The ..._ex forms take options (NULL = all defaults, as the plain forms). */
LOCUS_API locus_status locus_session_create_from_file_ex(const char* path, const locus_session_options* opt,
                                                         locus_session** out);

/* The operator a session runs on: LOCUS_OPERATOR_COTAN or LOCUS_OPERATOR_ROBUST;
 * -1 (with a message) when session is NULL. Thread-safe. */
LOCUS_API int32_t locus_session_operator(const locus_session* session);

/* A new session from arrays (copied; the caller keeps ownership):
 * xyz: 3 * nv doubles, vertex i at xyz[3i .. 3i+2], finite;
 * tris: 3 * nf vertex ids, triangle f = tris[3f .. 3f+2], each in [0, nv);
 * 1 <= nv < 2^31 - 1 and 1 <= nf <= (2^31 - 1) / 3 (LOCUS_BAD_USAGE otherwise).
 * The arrays must hold that many elements (locus cannot check a pointer's size).
 * Same mesh requirements as locus_session_create_from_file. Thread-safe. */
LOCUS_API locus_status locus_session_create(const double* xyz, int64_t nv, const int32_t* tris, int64_t nf,
                                            locus_session** out);
LOCUS_API locus_status locus_session_create_ex(const double* xyz, int64_t nv, const int32_t* tris, int64_t nf,
                                               const locus_session_options* opt, locus_session** out);

/* A triangle mesh in the caller's own buffers: positions as
 * float or double, ids as uint16, uint32 or int32, each at a byte stride, as
 * game engines keep them in interleaved vertex and index buffers. No alignment
 * is needed. float -> double and the id conversions are exact: a view gives
 * bit-identical results to double/int32 arrays holding the same values. */
typedef enum locus_scalar_type { LOCUS_FLOAT32 = 1, LOCUS_FLOAT64 = 2 } locus_scalar_type;
typedef enum locus_index_type { LOCUS_UINT16 = 1, LOCUS_UINT32 = 2, LOCUS_INT32 = 3 } locus_index_type;
typedef struct locus_mesh_view {
  const void* positions;   /* vertex i: x, y, z (consecutive) at (const char*)positions + i * position_stride */
  int32_t position_type;   /* locus_scalar_type */
  int64_t position_stride; /* bytes between vertices; 0 = tightly packed (3 values) */
  int64_t vertex_count;    /* 1 <= vertex_count < 2^31 - 1 */
  const void* indices;     /* triangle f: 3 ids (consecutive) at (const char*)indices + f * index_stride */
  int32_t index_type;      /* locus_index_type */
  int64_t index_stride;    /* bytes between triangles; 0 = tightly packed (3 ids) */
  int64_t triangle_count;  /* 1 <= triangle_count <= (2^31 - 1) / 3 */
} locus_mesh_view;

/* A new session from a mesh view: the buffers are read once into the
 * session's own arrays (the one copy locus makes; the caller keeps ownership
 * and may free them after the call). LOCUS_BAD_USAGE for a NULL pointer, a
 * count, stride or type out of range or a vertex id out of range (naming the
 * triangle); otherwise the requirements of locus_session_create_from_file.
 * Thread-safe. */
LOCUS_API locus_status locus_session_create_from_view(const locus_mesh_view* view, locus_session** out);
LOCUS_API locus_status locus_session_create_from_view_ex(const locus_mesh_view* view, const locus_session_options* opt,
                                                         locus_session** out);

/* Polygon meshes (quads, mixed, n-gons). Faces in CSR form:
 * face f's corners are face_indices[face_offsets[f] .. face_offsets[f + 1]),
 * face_offsets has nf + 1 entries, face_offsets[0] = 0 (LOCUS_BAD_USAGE
 * otherwise, as for an id out of range); a face of fewer than 3 corners or one
 * that is no simple polygon (its corners on a line, its boundary crossing
 * itself) is LOCUS_BAD_INPUT naming the face; the other requirements are those
 * of locus_session_create_from_file. Triangles may be mixed in.
 * The session triangulates the polygons once (ear clipping) keeping the
 * vertices, so every per-vertex output indexes the caller's vertices. As the
 * `locus` CLI on the same file: locus_geodesic_distance and locus_logmap run
 * on the polygons themselves (the polygon heat method, full solves; default
 * t_factor 8; the log map's disk grows over the polygon edges), the other
 * calls on the triangulation; face ids (locus_surface_point, outputs) and
 * locus_session_face_count are the triangulation's.
 * xyz: 3 * nv doubles as in locus_session_create. Thread-safe. */
LOCUS_API locus_status locus_session_create_polygons(const double* xyz, int64_t nv, const int32_t* face_offsets,
                                                     const int32_t* face_indices, int64_t nf, locus_session** out);

/* The same from the caller's buffers: positions as in locus_mesh_view,
 * face_offsets (face_count + 1 entries) and face_indices packed, both of
 * index_type (locus_index_type). */
typedef struct locus_polygon_view {
  const void* positions;   /* as locus_mesh_view */
  int32_t position_type;   /* locus_scalar_type */
  int64_t position_stride; /* bytes between vertices; 0 = tightly packed (3 values) */
  int64_t vertex_count;    /* 1 <= vertex_count < 2^31 - 1 */
  const void* face_offsets; /* face_count + 1 ids of index_type, the first 0 */
  const void* face_indices; /* face_offsets[face_count] ids of index_type */
  int32_t index_type;      /* locus_index_type */
  int64_t face_count;      /* 1 <= face_count <= (2^31 - 1) / 3 */
} locus_polygon_view;
LOCUS_API locus_status locus_session_create_from_polygon_view(const locus_polygon_view* view, locus_session** out);

/* Frees the session and everything it cached. NULL is a no-op. Not concurrently
 * with other calls on the same session. */
LOCUS_API void locus_session_destroy(locus_session* session);

/* Number of vertices, or -1 (with a message) when session is NULL. */
LOCUS_API int64_t locus_session_vertex_count(const locus_session* session);

/* Number of triangles (of the triangulation, for a polygon mesh), or -1 (with
 * a message) when session is NULL. */
LOCUS_API int64_t locus_session_face_count(const locus_session* session);

/* Copies the current vertex positions into out_xyz (3 * vertex-count doubles,
 * vertex i at out_xyz[3i .. 3i+2]). */
LOCUS_API locus_status locus_session_get_positions(const locus_session* session, double* out_xyz);

/* Replaces the vertex positions (3 * nv finite doubles, nv = the vertex count)
 * keeping the connectivity. Factors that depend on positions are rebuilt on
 * the next query; orderings and symbolic factors are kept. Safe concurrently
 * with queries (running ones finish on the old positions). On failure (e.g. a
 * face becomes degenerate: LOCUS_BAD_INPUT) the old positions stay. */
LOCUS_API locus_status locus_session_set_positions(locus_session* session, const double* xyz, int64_t nv);

/* Heat geodesic distance (Crane et al., thesis §6.4) from vertex `source` to
 * every vertex: out_nv receives vertex-count doubles, 0 at the source, NaN
 * (no value: see locus_valid_mask) at vertices in another connected component
 * than the source.
 * The first call factors the two heat-method operators (the long part);
 * later calls cost two solves. */
LOCUS_API locus_status locus_geodesic_distance(locus_session* session, int64_t source, double* out_nv);
/* The same with options (progress/cancel, threads, t_factor); opts may be NULL. */
LOCUS_API locus_status locus_geodesic_distance_ex(locus_session* session, int64_t source, double* out_nv,
                                                  const locus_run_options* opts);

/* No value. Every output of this API that has no value at a vertex (outside a
 * log-map or parameterization patch, a geodesic distance in another connected
 * component than the sources) holds NaN there, never an infinity, as the
 * `locus` CLI writes it; locus_valid_mask gives the CLI's integer mask `valid`
 * (1 = has a value) for such an output: out_valid[i] = !isnan(values[i * stride])
 * for i < count (stride >= 1, in doubles: 1 for distances, 2 for (u, v)
 * pairs). Returns the number of vertices with a value, or -1 (with a message)
 * when a pointer is NULL or count < 0 or stride < 1. */
LOCUS_API int64_t locus_valid_mask(const double* values, int64_t count, int64_t stride, int32_t* out_valid);

/* Heat log map (thesis §6.5–6.6) of the geodesic disk of round(fraction * nv)
 * vertices (at least 1) around vertex `center`, 0 < fraction <= 1.
 * out_uv: 2 * vertex-count doubles; vertex i gets (u, v) at out_uv[2i], out_uv[2i+1]
 * (geodesic polar coordinates in the tangent plane of the center) when it lies
 * in the disk, NaN in both otherwise. Shares its factors with the geodesic distance. */
LOCUS_API locus_status locus_logmap(locus_session* session, int64_t center, double fraction, double* out_uv);
LOCUS_API locus_status locus_logmap_ex(locus_session* session, int64_t center, double fraction, double* out_uv,
                                       const locus_run_options* opts);

/* ---- The geodesic and logmap commands, every option of `locus geodesic` and
 * `locus logmap` (engine/include/locus/engine/geodesic_requests.hpp) ----
 * Each field is the CLI's option of the same name ('-' as '_') with its
 * default; locus_*_options_default() returns the defaults (a zero-initialized
 * struct is not the default here: fraction is not 0). Strings are
 * NUL-terminated; NULL or "" means the default (or none). Diffusion time: `t`
 * as text ("4h2": a multiple of h^2, h the mean edge length; "0.001": an
 * absolute time) or t_factor = C for "Ch2" (0: not given; not both); default
 * 4h2, 8h2 on polygon meshes. save/load: a factor cache file of the heat
 * method's two factors (written after factoring / read instead of factoring,
 * refused with LOCUS_BAD_INPUT when made for another mesh or t). The argument
 * checks are the CLI's, with its messages. opts->t_factor must be 0 here. */
typedef struct locus_geodesic_options {
  int64_t source;    /* source vertex (no default: -1) */
  double fraction;   /* (0, 1]: 1 (default) the whole mesh, else the geodesic disk of round(fraction * nv) vertices */
  const char* t;     /* NULL: default */
  double t_factor;   /* 0: not given */
  const char* save;  /* NULL: none */
  const char* load;  /* NULL: none */
} locus_geodesic_options;
LOCUS_API locus_geodesic_options locus_geodesic_options_default(void);

/* What a geodesic run reports beside the distances (as `locus geodesic --json`). */
typedef struct locus_geodesic_report {
  int64_t patch_size;               /* vertices computed */
  double t_factor, t, h;            /* the time used (t = t_factor h^2) and the mean edge length */
  double max_distance;
  int64_t unreachable;              /* vertices in other connected components (NaN) */
  int64_t heat_underflow_vertices;  /* the heat underflowed there (distances interpolated) */
  double t_avoiding_underflow;      /* a t that avoids it (0: none underflowed) */
  double precompute_s, patch_s, query_s;
} locus_geodesic_report;

/* Heat geodesic distance with every option: out_nv receives vertex-count
 * doubles, NaN (no value) outside the patch and in other components than the
 * source. out_report may be NULL. The numbers are `locus geodesic`'s, bit for bit. */
LOCUS_API locus_status locus_geodesic_run(locus_session* session, const locus_geodesic_options* options, double* out_nv,
                                          locus_geodesic_report* out_report, const locus_run_options* opts);

typedef struct locus_logmap_options {
  int64_t center;          /* center vertex (no default: -1) */
  double fraction;         /* (0, 1], default 0.05 */
  const char* t;           /* NULL: default */
  double t_factor;         /* 0: not given */
  const char* method;      /* "heat" (default, localized), "heat-full" or "dem" */
  const char* angle;       /* "auto" (default), "log", "two-ring" or "average" */
  const char* lattice;     /* "default" (the library's, path), "none", "star", "ring" or "path" */
  const char* recenter;    /* "default" (the library's, on), "on" or "off" */
  int32_t clip_injective;  /* nonzero: keep only the patch vertices inside the injectivity radius */
  const char* save;        /* NULL: none */
  const char* load;        /* NULL: none */
} locus_logmap_options;
LOCUS_API locus_logmap_options locus_logmap_options_default(void);

/* What a log map run reports beside the map (as `locus logmap --json`). */
typedef struct locus_logmap_report {
  int64_t patch_size;       /* vertices of the map (after clip_injective) */
  double t_factor, t, h;    /* t, h: 0 for the DEM */
  double max_distance;
  int64_t flipped;          /* flipped triangles (polygons on a polygon mesh) */
  double injectivity_radius; /* INFINITY when none flipped */
  int32_t clipped_vertices;
  int32_t sources, batches, passes, angle_fallbacks, two_ring, recentered;  /* heat methods */
  int64_t heat_underflow_vertices;
  double t_avoiding_underflow;
  double precompute_s, patch_s, query_s;
} locus_logmap_report;

/* Log map with every option: out_uv (2 * vertex-count doubles) as locus_logmap;
 * out_distance and out_angle (vertex-count doubles each, may be NULL) the
 * geodesic distance and polar angle, NaN outside the map; out_report may be
 * NULL. The numbers are `locus logmap`'s, bit for bit. */
LOCUS_API locus_status locus_logmap_run(locus_session* session, const locus_logmap_options* options, double* out_uv,
                                        double* out_distance, double* out_angle, locus_logmap_report* out_report,
                                        const locus_run_options* opts);

/* Centroidal Voronoi tessellation by localized heat Lloyd iterations (thesis
 * §3.7; cells and centroids by M - 4h^2 L): `sites` seeded random initial
 * sites (>= 1, else LOCUS_BAD_USAGE; at most the vertex count and one per
 * connected component, else LOCUS_BAD_INPUT), 0 <= iters <= 10000 iterations. out_labels_nv: vertex-count
 * int32 labels in [0, sites). The same seed gives the same labels for any
 * thread count. */
LOCUS_API locus_status locus_cvt(locus_session* session, int32_t sites, int32_t iters, uint64_t seed,
                                 int32_t* out_labels_nv);
/* The same with options; with out_sites_xyz non-NULL (3 * sites doubles) also the
 * final site positions. opts may be NULL. */
LOCUS_API locus_status locus_cvt_ex(locus_session* session, int32_t sites, int32_t iters, uint64_t seed,
                                    int32_t* out_labels_nv, double* out_sites_xyz, const locus_run_options* opts);

/* CVT remeshing: the heat CVT as above, then the restricted-Delaunay
 * dual of its cells, made a closed manifold with the mesh's genus, components
 * and boundary loops by adding sites where needed, and optimized on the surface.
 * The result is an opaque handle (free it with locus_remesh_destroy); *out is
 * set only on LOCUS_OK. LOCUS_NUMERICAL when the cells still break the
 * closed-ball property after the repair rounds (e.g. far too few sites for the
 * mesh's handles or holes). opts may be NULL; its t_factor must be 0. */
typedef struct locus_remesh locus_remesh;
typedef struct locus_remesh_stats {
  int64_t vertices, faces;
  int32_t manifold;            /* 1 when the remesh is a manifold */
  int64_t genus;               /* summed over components */
  int32_t components, boundary_loops;
  double mean_min_angle_deg;   /* mean over triangles of the smallest angle */
  double min_angle_deg;
  double pct_below_30_deg;
  double hausdorff_rel;        /* to the input, relative to its bounding-box diagonal */
  int32_t added_sites;
} locus_remesh_stats;
LOCUS_API locus_status locus_cvt_remesh(locus_session* session, int32_t sites, int32_t iters, uint64_t seed,
                                        const locus_run_options* opts, locus_remesh** out);
/* out_xyz: 3 * vertices doubles; out_tris: 3 * faces int32 (either may be NULL). */
LOCUS_API locus_status locus_remesh_get(const locus_remesh* remesh, double* out_xyz, int32_t* out_tris);
LOCUS_API locus_status locus_remesh_get_stats(const locus_remesh* remesh, locus_remesh_stats* out);
LOCUS_API void locus_remesh_destroy(locus_remesh* remesh);

/* Entries of the inverse heat operator (M - tL)^{-1} between vertex sets, by
 * exact local solves: out[s * n_targets + k] = value at targets[k] of the heat
 * from sources[s] (n_sources * n_targets doubles). Counts >= 1 and ids in range;
 * n_sources * n_targets <= 2^28. Repeated ids are allowed. opts may be NULL. */
LOCUS_API locus_status locus_heat_values(locus_session* session, const int64_t* sources, int64_t n_sources,
                                         const int64_t* targets, int64_t n_targets, double* out,
                                         const locus_run_options* opts);

/* ==== Diffusion, deformation and shape. Every call below reuses the session's
 * cached factors: the heat operator M - tL once per t (shared by Voronoi,
 * natural neighbors, skinning, ADF/HKS, heat exchange and heat values), the
 * heat-method factors once per t_factor (geodesic distance, log map), -L + eps M
 * once (patch parameterization). Ids out of range (vertices, faces, edges) are
 * LOCUS_BAD_USAGE. ==== */

/* Builds cached operators now instead of at the first query that needs them
 * (e.g. on a loading screen, before handing the session to worker threads):
 * `operators` is a combination of the flags below; t from opts->t_factor. */
#define LOCUS_PREPARE_HEAT_METHOD 1 /* geodesic distance, log map */
#define LOCUS_PREPARE_DIFFUSION 2   /* M - tL: Voronoi, natural neighbors, skinning, ADF/HKS, heat exchange/values */
#define LOCUS_PREPARE_LAPLACIAN 4   /* -L + eps M: patch parameterization */
LOCUS_API locus_status locus_session_prepare(locus_session* session, int32_t operators, const locus_run_options* opts);

/* A point on the surface: a vertex (face < 0: `vertex`), or a face and the
 * barycentric weights of its three corners (in the order of the triangle as
 * given), each >= 0, summing to 1. */
typedef struct locus_surface_point {
  int64_t face;
  int64_t vertex;
  double bary[3];
} locus_surface_point;

/* `count` points uniformly distributed by area into out (count entries), from
 * a splitmix64 stream seeded with `seed`: the same on every platform, and the
 * generators of `locus voronoi --random count --seed seed`. */
LOCUS_API locus_status locus_random_surface_points(const locus_session* session, int64_t count, uint64_t seed,
                                                   locus_surface_point* out);

/* ---- Multi-source geodesic distance ----
 * Heat geodesic distance from a set of sources (vertices and points in faces)
 * at once: one heat solve with every source's hat weights, one Poisson solve.
 * Per connected component the distance is shifted so that its minimum over the
 * component's sources is 0; NaN (no value) in components without a source.
 * out_nv: vertex-count doubles. n_sources >= 1. opts->t_factor as for
 * locus_geodesic_distance (the same cached factors). */
LOCUS_API locus_status locus_geodesic_distance_multi(locus_session* session, const locus_surface_point* sources,
                                                     int64_t n_sources, double* out_nv, const locus_run_options* opts);

/* ---- Heat Voronoi diagram (thesis §3.4) ----
 * Cells of 1..vertex-count generators by the hottest generator (t =
 * opts->t_factor * h^2, default h^2, as for every diffusion call below), and the bisector curves
 * as polylines through points on mesh edges and Voronoi corners.
 * Outputs (caller-owned; a NULL array with capacity 0 skips it):
 *   labels: vertex-count int32 generator indices;
 *   points: 3 doubles per diagram point, points_capacity points;
 *   line_offsets: n_lines + 1 entries (polyline k = line_points[line_offsets[k] ..
 *     line_offsets[k+1])), lines_capacity polylines;
 *   line_points: point ids, line_points_capacity entries.
 * The counts n_points, n_lines, n_line_points are always written; when a
 * capacity is too small the call returns LOCUS_BAD_USAGE naming it and writes
 * no array but the labels. locus_voronoi_bound gives capacities that always suffice. */
typedef struct locus_voronoi_output {
  int32_t* labels;
  double* points;
  int64_t points_capacity;
  int64_t n_points;
  int64_t* line_offsets;
  int64_t lines_capacity;
  int64_t n_lines;
  int64_t* line_points;
  int64_t line_points_capacity;
  int64_t n_line_points;
} locus_voronoi_output;
/* Upper bounds for any generator set: points <= 4 * faces, lines <= 3 * faces,
 * line points <= 6 * faces. Any pointer may be NULL. */
LOCUS_API locus_status locus_voronoi_bound(const locus_session* session, int64_t* max_points, int64_t* max_lines,
                                           int64_t* max_line_points);
LOCUS_API locus_status locus_voronoi(locus_session* session, const locus_surface_point* generators,
                                     int64_t n_generators,
                                     locus_voronoi_output* out, const locus_run_options* opts);

/* ---- Natural-neighbor coordinates (thesis §3.7.2) ----
 * Area-stealing coordinates of a surface point with respect to sites, with heat
 * Voronoi cells. Prepared tier: locus_nncoords_prepare computes the sites'
 * diagram once; locus_nncoords_query then answers any number of points, from any
 * number of threads at once (the handle is immutable). The handle keeps what it
 * needs alive: it stays valid after locus_session_set_positions (old positions)
 * and after locus_session_destroy. One-shot tier: locus_nncoords.
 * out_weights: one double per site (>= 0, summing to 1). */
typedef struct locus_nncoords_field locus_nncoords_field;
LOCUS_API locus_status locus_nncoords_prepare(locus_session* session, const locus_surface_point* sites, int64_t n_sites,
                                              const locus_run_options* opts, locus_nncoords_field** out);
LOCUS_API locus_status locus_nncoords_query(const locus_nncoords_field* nn, const locus_surface_point* point,
                                            double* out_weights);
LOCUS_API int64_t locus_nncoords_site_count(const locus_nncoords_field* nn); /* -1 when nn is NULL */
LOCUS_API void locus_nncoords_destroy(locus_nncoords_field* nn);
LOCUS_API locus_status locus_nncoords(locus_session* session, const locus_surface_point* sites, int64_t n_sites,
                                      const locus_surface_point* point, double* out_weights,
                                      const locus_run_options* opts);

/* ---- Skinning weights (thesis §3.7.2) ----
 * Natural-neighbor coordinates of every vertex with respect to the handles:
 * out: vertex-count * n_handles doubles, vertex v's weights at out[v * n_handles ..]. */
LOCUS_API locus_status locus_skinning_weights(locus_session* session, const locus_surface_point* handles,
                                              int64_t n_handles,
                                              double* out, const locus_run_options* opts);

/* Every option of `locus skinweights` (vertex sets, bones, the methods): locus_skinweights_run in locus_commands.h. */

/* ---- Auto-diffusion function and heat kernel signature (thesis §4.6) ----
 * (M - tL)^{-1}_vv at the given vertices (vertices NULL and n_vertices 0: every
 * vertex, in order). locus_adf: one t (from opts), out: one double per vertex.
 * locus_hks: t_j = t_factors[j] * h^2, out[k * n_times + j]. selected_inversion
 * nonzero: all diagonal entries at once (faster for all vertices), else one
 * etree path per vertex; the values agree to rounding. */
LOCUS_API locus_status locus_adf(locus_session* session, const int64_t* vertices, int64_t n_vertices,
                                 int32_t selected_inversion,
                                 double* out, const locus_run_options* opts);
LOCUS_API locus_status locus_hks(locus_session* session, const double* t_factors, int64_t n_times,
                                 const int64_t* vertices,
                                 int64_t n_vertices, int32_t selected_inversion, double* out,
                                 const locus_run_options* opts);

/* ---- Pairwise heat exchange (thesis §4.6) ----
 * Unit heat at every source (repeats add), one step of M - tL; out_targets[k] =
 * heat at targets[k] (separate etree subtrees for the two sets: exact). */
LOCUS_API locus_status locus_heat_exchange(locus_session* session, const int64_t* sources, int64_t n_sources,
                                           const int64_t* targets, int64_t n_targets, double* out_targets,
                                           const locus_run_options* opts);

/* ---- Region-of-interest deformation (thesis §5.1, §5.7) ----
 * Moves the handle (handle_vertex and its handle_ring-ring inside the ROI) by
 * `offset` inside the breadth-first ROI of round(roi_fraction * nv) vertices
 * around roi_seed; outside the ROI nothing moves. The global factor is computed
 * once per energy and kept; each call derives the ROI's factor by the
 * factor-once update. out_xyz: 3 * vertex-count doubles; the session's
 * positions do not change. */
typedef struct locus_deform_request {
  int64_t roi_seed;
  double roi_fraction;  /* in (0, 1] */
  int64_t handle_vertex;
  int32_t handle_ring;  /* >= 0 */
  int32_t bilaplacian;  /* 0: Laplacian energy, nonzero: bilaplacian */
  double offset[3];
} locus_deform_request;
LOCUS_API locus_status locus_deform(locus_session* session, const locus_deform_request* request, double* out_xyz,
                                    const locus_run_options* opts);

/* ---- Parameterization ----
 * Disk (thesis §2.6): the whole mesh, which must be a disk; boundary on the unit
 * circle; method 0 perfect (Algorithm 1, max_iterations, eps), 1 cotan,
 * 2 uniform. out_uv: 2 * vertex-count doubles. out_flipped may be NULL. */
LOCUS_API locus_status locus_param_disk(locus_session* session, int32_t method, int32_t max_iterations, double eps,
                                        double* out_uv, int64_t* out_flipped, const locus_run_options* opts);
/* Patch (thesis §4.4): the breadth-first patch of round(fraction * nv)
 * vertices around `center`, from the session's factor of -L + eps M: boundary 0
 * Neumann (eq. 4.6), 1 circle (boundary fixed on a circle, holes filled).
 * out_uv: 2 * vertex-count doubles, NaN outside the patch; out_patch_size and
 * out_flipped may be NULL. */
LOCUS_API locus_status locus_param_patch(locus_session* session, int64_t center, double fraction, int32_t boundary,
                                         double* out_uv, int64_t* out_patch_size, int64_t* out_flipped,
                                         const locus_run_options* opts);

/* ---- Perfect Laplacian and self-supporting surface (thesis chapter 2) ----
 * Per unique edge of the faces (of the polygons as given for a polygon mesh:
 * locus_session_edge_count edges, each with
 * v0 < v1 in out_edges[2e], out_edges[2e+1]). out_xyz: 3 * vertex-count doubles
 * (perfect Laplacian: the embedding, aligned onto the input by a similarity in
 * space; self-supporting: the equilibrium surface). Any output may be NULL.
 * out_converged: 1 when the iteration converged within max_iterations. */
LOCUS_API int64_t locus_session_edge_count(const locus_session* session); /* -1 when session is NULL */
LOCUS_API locus_status locus_perfect_laplacian(locus_session* session, int32_t planar, int32_t max_iterations,
                                               double eps,
                                               int32_t* out_edges, double* out_weights, double* out_xyz,
                                               int32_t* out_converged, const locus_run_options* opts);
/* Supports on every boundary loop (the mesh needs one); dead load load_density per unit area. */
LOCUS_API locus_status locus_self_supporting(locus_session* session, double load_density, int32_t max_iterations,
                                             double eps,
                                             int32_t* out_edges, double* out_forces, double* out_xyz,
                                             int32_t* out_converged,
                                             const locus_run_options* opts);

LOCUS_API_END
#ifdef __cplusplus
}
#endif

/* The CLI commands with every option (locus_<command>_options, _run). */
#include "locus/locus_commands.h"

#endif /* LOCUS_LOCUS_H */
