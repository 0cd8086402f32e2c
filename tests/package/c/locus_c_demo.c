/* A C program that uses only <locus/locus.h>, built against the installed
 * package (tests/package/run_package_test.cmake). With a mesh path argument it
 * creates a session from that file (armadillo in the test), computes a heat
 * geodesic distance, a log map and a 100-site CVT, prints the figures and
 * checks that they are sane; it always also builds a session from arrays (an
 * octahedron refined to a sphere) and checks distances against great circles.
 * With LOCUS_PACKAGE_REFS set (make_references.cmake) it also calls every
 * pipeline of the C API and compares with the CLI's outputs for the same arguments.
 * Exit status 0 when every check passes, 1 otherwise. */
#include <locus/locus.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define EXPECT(cond, ...)                         \
  do {                                            \
    if (!(cond)) {                                \
      fprintf(stderr, "FAILED: %s: ", #cond);     \
      fprintf(stderr, __VA_ARGS__);               \
      fprintf(stderr, "\n");                      \
      ++failures;                                 \
    }                                             \
  } while (0)

static int call_ok(locus_status st, const char* what) {
  if (st != LOCUS_OK) {
    fprintf(stderr, "FAILED: %s returned %d: %s\n", what, (int)st, locus_last_error_message());
    ++failures;
    return 0;
  }
  return 1;
}

static int progress_calls = 0;
static int on_progress(double fraction, const char* phase, void* user) {
  (void)user;
  (void)phase;
  if (fraction >= 0.0 && fraction <= 1.0) ++progress_calls;
  return 0;
}

static double dist3(const double* a, const double* b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return sqrt(dx * dx + dy * dy + dz * dz);
}

static void file_checks(const char* path) {
  locus_session* s = NULL;
  if (!call_ok(locus_session_create_from_file(path, &s), "locus_session_create_from_file")) return;
  const int64_t nv = locus_session_vertex_count(s);
  printf("mesh %s: %lld vertices, %lld triangles\n", path, (long long)nv, (long long)locus_session_face_count(s));
  EXPECT(nv > 0, "vertex count %lld", (long long)nv);

  double* xyz = malloc(sizeof(double) * 3 * (size_t)nv);
  double* d = malloc(sizeof(double) * (size_t)nv);
  double* uv = malloc(sizeof(double) * 2 * (size_t)nv);
  int32_t* labels = malloc(sizeof(int32_t) * (size_t)nv);
  if (!xyz || !d || !uv || !labels) {
    fprintf(stderr, "out of memory\n");
    exit(1);
  }
  call_ok(locus_session_get_positions(s, xyz), "locus_session_get_positions");

  /* Geodesic distance from vertex 0: 0 at the source, finite, never much below
   * the straight-line distance, never above a multiple of the mesh diameter. */
  locus_run_options opts = locus_run_options_default();
  opts.progress = on_progress;
  if (call_ok(locus_geodesic_distance_ex(s, 0, d, &opts), "locus_geodesic_distance_ex")) {
    double dmax = 0, ratio_min = 1e300, diam = 0;
    int64_t bad = 0;
    for (int64_t i = 0; i < nv; ++i) {
      const double e = dist3(xyz + 3 * i, xyz);
      if (e > diam) diam = e;
    }
    /* The heat method smooths the distance within a few edges of the source
     * (t = h^2), so compare with the straight line beyond 5% of the extent. */
    for (int64_t i = 0; i < nv; ++i) {
      if (!isfinite(d[i])) ++bad;
      if (d[i] > dmax) dmax = d[i];
      const double e = dist3(xyz + 3 * i, xyz);
      if (e > 0.05 * diam && d[i] / e < ratio_min) ratio_min = d[i] / e;
    }
    printf("geodesic from 0: max %.6g, straight-line max %.6g, min geodesic/straight (beyond 5%%) %.4f\n", dmax, diam, ratio_min);
    EXPECT(d[0] == 0.0, "d[0] = %g", d[0]);
    EXPECT(bad == 0, "%lld non-finite distances", (long long)bad);
    EXPECT(ratio_min > 0.8, "a geodesic distance is far below the straight line (ratio %g)", ratio_min);
    EXPECT(dmax >= 0.9 * diam && dmax < 5 * diam, "max distance %g vs straight-line %g", dmax, diam);
  }

  /* Log map of the disk of 5% of the vertices around vertex 0: NaN outside,
   * |(u, v)| close to the geodesic distance inside. */
  if (call_ok(locus_logmap(s, 0, 0.05, uv), "locus_logmap")) {
    int64_t inside = 0;
    double worst = 0, rmax = 0;
    for (int64_t i = 0; i < nv; ++i) {
      if (isnan(uv[2 * i]) != isnan(uv[2 * i + 1])) ++failures;
      if (isnan(uv[2 * i])) continue;
      ++inside;
      const double r = hypot(uv[2 * i], uv[2 * i + 1]);
      if (r > rmax) rmax = r;
      if (fabs(r - d[i]) > worst) worst = fabs(r - d[i]);
    }
    const int64_t want = (int64_t)floor(0.05 * (double)nv + 0.5);
    printf("log map at 0: %lld vertices in the patch (want %lld), radius %.6g, max | |uv| - geodesic | %.4g\n",
           (long long)inside, (long long)want, rmax, worst);
    EXPECT(inside == want, "patch size %lld", (long long)inside);
    EXPECT(uv[0] == 0.0 && uv[1] == 0.0, "center at (%g, %g)", uv[0], uv[1]);
    EXPECT(rmax > 0 && worst < 0.1 * rmax, "log-map radius %g vs geodesic, worst difference %g", rmax, worst);
  }

  /* 100-site CVT: every label in range, every cell non-empty, sizes not absurd. */
  if (call_ok(locus_cvt_ex(s, 100, 10, 1, labels, NULL, &opts), "locus_cvt_ex")) {
    int64_t count[100];
    int64_t out_of_range = 0, cmin = nv, cmax = 0;
    memset(count, 0, sizeof count);
    for (int64_t i = 0; i < nv; ++i) {
      if (labels[i] < 0 || labels[i] >= 100) {
        ++out_of_range;
        continue;
      }
      ++count[labels[i]];
    }
    for (int k = 0; k < 100; ++k) {
      if (count[k] < cmin) cmin = count[k];
      if (count[k] > cmax) cmax = count[k];
    }
    printf("cvt 100 sites, 10 iterations: cell sizes %lld..%lld vertices (mean %lld)\n", (long long)cmin,
           (long long)cmax, (long long)(nv / 100));
    EXPECT(out_of_range == 0, "%lld labels out of range", (long long)out_of_range);
    EXPECT(cmin > 0, "an empty cell");
    EXPECT(cmax < 10 * (nv / 100), "a cell of %lld vertices", (long long)cmax);
  }
  printf("progress reports: %d\n", progress_calls);
  EXPECT(progress_calls > 0, "no progress report");

  /* Errors come back as status codes with a message, never as a crash. */
  EXPECT(locus_geodesic_distance(s, nv, d) == LOCUS_BAD_USAGE, "out-of-range source accepted");
  EXPECT(strstr(locus_last_error_message(), "source") != NULL, "message: %s", locus_last_error_message());
  EXPECT(locus_logmap(s, 0, 0.0, uv) == LOCUS_BAD_USAGE, "fraction 0 accepted");
  EXPECT(locus_cvt(s, 100, 10, 1, NULL) == LOCUS_BAD_USAGE, "NULL labels accepted");

  free(xyz);
  free(d);
  free(uv);
  free(labels);
  locus_session_destroy(s);
}

/* Octahedron refined `levels` times by 1:4 midpoint subdivision, projected on the unit sphere. */
static void sphere_checks(int levels) {
  int64_t nv = 6, nf = 8;
  int64_t cap_v = 6, cap_f = 8;
  for (int l = 0; l < levels; ++l) {
    cap_f *= 4;
    cap_v += cap_f; /* generous: at most 3 new vertices per face */
  }
  double* xyz = malloc(sizeof(double) * 3 * (size_t)cap_v);
  int32_t* tris = malloc(sizeof(int32_t) * 3 * (size_t)cap_f);
  int32_t* next = malloc(sizeof(int32_t) * 3 * (size_t)cap_f);
  if (!xyz || !tris || !next) exit(1);
  const double v0[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  const int32_t f0[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  memcpy(xyz, v0, sizeof v0);
  memcpy(tris, f0, sizeof f0);
  for (int l = 0; l < levels; ++l) {
    /* Midpoints found by a linear scan of a per-level edge table (small meshes only). */
    int64_t ne = 0;
    int32_t* ea = malloc(sizeof(int32_t) * 3 * (size_t)nf);
    int32_t* eb = malloc(sizeof(int32_t) * 3 * (size_t)nf);
    int32_t* em = malloc(sizeof(int32_t) * 3 * (size_t)nf);
    if (!ea || !eb || !em) exit(1);
    for (int64_t f = 0; f < nf; ++f) {
      int32_t mid[3];
      for (int c = 0; c < 3; ++c) {
        int32_t a = tris[3 * f + c], b = tris[3 * f + (c + 1) % 3];
        if (a > b) {
          const int32_t t = a;
          a = b;
          b = t;
        }
        int64_t e = 0;
        while (e < ne && !(ea[e] == a && eb[e] == b)) ++e;
        if (e == ne) {
          double* p = xyz + 3 * nv;
          for (int k = 0; k < 3; ++k) p[k] = 0.5 * (xyz[3 * a + k] + xyz[3 * b + k]);
          const double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
          for (int k = 0; k < 3; ++k) p[k] /= r;
          ea[ne] = a;
          eb[ne] = b;
          em[ne] = (int32_t)nv++;
          ++ne;
        }
        mid[c] = em[e];
      }
      const int32_t A = tris[3 * f], B = tris[3 * f + 1], C = tris[3 * f + 2];
      const int32_t quad[12] = {A, mid[0], mid[2], mid[0], B, mid[1], mid[2], mid[1], C, mid[0], mid[1], mid[2]};
      memcpy(next + 12 * f, quad, sizeof quad);
    }
    nf *= 4;
    memcpy(tris, next, sizeof(int32_t) * 3 * (size_t)nf);
    free(ea);
    free(eb);
    free(em);
  }

  locus_session* s = NULL;
  if (call_ok(locus_session_create(xyz, nv, tris, nf, &s), "locus_session_create")) {
    double* d = malloc(sizeof(double) * (size_t)nv);
    if (!d) exit(1);
    if (call_ok(locus_geodesic_distance(s, 0, d), "locus_geodesic_distance (sphere)")) {
      double err = 0;
      for (int64_t i = 0; i < nv; ++i) {
        double c = xyz[3 * i]; /* source is (1, 0, 0) */
        if (c > 1) c = 1;
        if (c < -1) c = -1;
        err += fabs(d[i] - acos(c));
      }
      err /= (double)nv;
      printf("sphere (%lld vertices): mean |geodesic - great circle| = %.4g\n", (long long)nv, err);
      EXPECT(err < 0.05, "mean error %g", err);
    }
    free(d);
    locus_session_destroy(s);
  }
  /* Bad arrays: a face index out of range is a usage error (locus.h) with a message naming it. */
  tris[5] = (int32_t)nv;
  EXPECT(locus_session_create(xyz, nv, tris, nf, &s) == LOCUS_BAD_USAGE && s == NULL, "bad index accepted");
  EXPECT(strstr(locus_last_error_message(), "triangle 1") != NULL, "message: %s", locus_last_error_message());
  free(xyz);
  free(tris);
  free(next);
}

/* ==== Every pipeline of the C API against the CLI (tests/package/make_references.cmake
 * wrote the CLI's outputs for the same arguments into $LOCUS_PACKAGE_REFS). ==== */

static char* ref_path(const char* dir, const char* name) {
  static char buf[4096];
  snprintf(buf, sizeof buf, "%s/%s", dir, name);
  return buf;
}

static char* read_text(const char* path) {
  FILE* f = fopen(path, "rb");
  long n;
  char* s;
  if (!f) {
    fprintf(stderr, "FAILED: cannot open %s\n", path);
    ++failures;
    return NULL;
  }
  fseek(f, 0, SEEK_END);
  n = ftell(f);
  fseek(f, 0, SEEK_SET);
  s = malloc((size_t)n + 1);
  if (!s || fread(s, 1, (size_t)n, f) != (size_t)n) exit(1);
  s[n] = '\0';
  fclose(f);
  return s;
}

/* The numbers of the JSON value of "key" (a number or nested arrays of numbers), flattened. */
static int64_t json_numbers(const char* text, const char* key, double* out, int64_t max) {
  char pattern[256];
  const char* p;
  int depth = 0;
  int64_t n = 0;
  snprintf(pattern, sizeof pattern, "\"%s\":", key);
  p = text ? strstr(text, pattern) : NULL;
  if (!p) return -1;
  p += strlen(pattern);
  for (;;) {
    while (*p == ' ' || *p == '\n' || *p == ',') ++p;
    if (*p == '[') {
      ++depth;
      ++p;
    } else if (*p == ']') {
      --depth;
      ++p;
      if (depth == 0) break;
    } else {
      char* end;
      const double v = strtod(p, &end);
      if (end == p) break;
      if (n < max) out[n] = v;
      ++n;
      p = end;
      if (depth == 0) break;
    }
  }
  return n;
}

/* Vertex properties of a binary little-endian PLY written by locus (all doubles):
 * out[v * props + k]; returns the vertex count, props = doubles per vertex. */
/* The leading double properties of a binary PLY's vertices (x y z, then the
   results), nv rows of *props values. Later int properties (the `valid` mask)
   are skipped by their size. */
static int64_t ply_vertex_doubles(const char* path, double** out, int* props) {
  FILE* f = fopen(path, "rb");
  char line[512];
  int64_t nv = -1, v;
  int in_vertex = 0, ints = 0, k;
  size_t stride;
  unsigned char* row;
  *props = 0;
  *out = NULL;
  if (!f) return -1;
  while (fgets(line, sizeof line, f)) {
    if (strncmp(line, "element vertex ", 15) == 0) {
      nv = strtoll(line + 15, NULL, 10);
      in_vertex = 1;
    } else if (strncmp(line, "element ", 8) == 0) {
      in_vertex = 0;
    } else if (in_vertex && strncmp(line, "property double ", 16) == 0 && ints == 0) {
      ++*props;
    } else if (in_vertex && strncmp(line, "property int ", 13) == 0) {
      ++ints;
    } else if (strncmp(line, "end_header", 10) == 0) {
      break;
    }
  }
  stride = sizeof(double) * (size_t)*props + 4 * (size_t)ints;
  *out = malloc(sizeof(double) * (size_t)(nv * *props));
  row = malloc(stride);
  for (v = 0; nv > 0 && *out && row && v < nv; ++v) {
    if (fread(row, 1, stride, f) != stride) {
      nv = -1;
      break;
    }
    for (k = 0; k < *props; ++k) memcpy(*out + v * *props + k, row + sizeof(double) * (size_t)k, sizeof(double));
  }
  free(row);
  fclose(f);
  return nv;
}

/* The numbers after each line starting with `tag` ("v ", "vt ") of an OBJ file, `per` per line. */
static int64_t obj_numbers(const char* path, const char* tag, int per, double** out) {
  FILE* f = fopen(path, "rb");
  char line[1024];
  int64_t n = 0, cap = 1024;
  const size_t len = strlen(tag);
  *out = malloc(sizeof(double) * (size_t)(cap * per));
  if (!f || !*out) return -1;
  while (fgets(line, sizeof line, f)) {
    char* p = line + len;
    int k;
    if (strncmp(line, tag, len) != 0) continue;
    if (n == cap) {
      cap *= 2;
      *out = realloc(*out, sizeof(double) * (size_t)(cap * per));
      if (!*out) exit(1);
    }
    for (k = 0; k < per; ++k) (*out)[n * per + k] = strtod(p, &p);
    ++n;
  }
  fclose(f);
  return n;
}

/* max |a - b| / max(max |b|, tiny) over n values; prints it and counts a failure above tol. */
static void compare(const char* what, const double* a, const double* b, int64_t n, double tol) {
  double diff = 0, scale = 1e-300;
  int64_t i;
  for (i = 0; i < n; ++i) {
    const double d = fabs(a[i] - b[i]);
    if (!(d <= diff)) diff = d; /* NaN counts as a difference */
    if (fabs(b[i]) > scale) scale = fabs(b[i]);
  }
  printf("  %-34s %8lld values, max |api - cli| / max |cli| = %.3g\n", what, (long long)n, diff / scale);
  EXPECT(n > 0 && diff / scale <= tol, "%s differs from the CLI (%.3g)", what, diff / scale);
}

static int cmp_double(const void* a, const void* b) {
  const double x = *(const double*)a, y = *(const double*)b;
  return (x > y) - (x < y);
}

/* The patch's (u, v) from the API (NaN outside) against the OBJ's vt lines, as sorted lists
 * (the OBJ numbers the patch's vertices its own way). */
static void compare_patch_uv(const char* what, const double* uv_nv, int64_t nv, const char* obj) {
  double* vt = NULL;
  const int64_t n = obj_numbers(obj, "vt ", 2, &vt);
  double* a = malloc(sizeof(double) * 2 * (size_t)(n > 0 ? n : 1));
  double* b = malloc(sizeof(double) * 2 * (size_t)(n > 0 ? n : 1));
  int64_t m = 0, i;
  if (!a || !b) exit(1);
  for (i = 0; i < nv; ++i)
    if (!isnan(uv_nv[2 * i])) {
      if (m < n) {
        a[m] = uv_nv[2 * i];
        a[n + m] = uv_nv[2 * i + 1];
      }
      ++m;
    }
  EXPECT(m == n, "%s: %lld patch vertices, the CLI has %lld", what, (long long)m, (long long)n);
  if (m == n && n > 0) {
    for (i = 0; i < n; ++i) {
      b[i] = vt[2 * i];
      b[n + i] = vt[2 * i + 1];
    }
    qsort(a, (size_t)n, sizeof(double), cmp_double);
    qsort(a + n, (size_t)n, sizeof(double), cmp_double);
    qsort(b, (size_t)n, sizeof(double), cmp_double);
    qsort(b + n, (size_t)n, sizeof(double), cmp_double);
    compare(what, a, b, 2 * n, 1e-9);
  }
  free(vt);
  free(a);
  free(b);
}

/* Edges and per-edge values of a "v0 v1 value" text file against the API's arrays. */
static void compare_edge_file(const char* what, const char* path, const int32_t* edges, const double* values, int64_t ne) {
  FILE* f = fopen(path, "r");
  double* ref = malloc(sizeof(double) * (size_t)ne);
  int64_t n = 0, wrong_edges = 0;
  int a, b;
  double w;
  if (!f || !ref) {
    EXPECT(0, "cannot read %s", path);
    free(ref);
    return;
  }
  while (n < ne && fscanf(f, "%d %d %lf", &a, &b, &w) == 3) {
    if (a != edges[2 * n] || b != edges[2 * n + 1]) ++wrong_edges;
    ref[n++] = w;
  }
  fclose(f);
  EXPECT(n == ne && wrong_edges == 0, "%s: %lld edges read, %lld differ", what, (long long)n, (long long)wrong_edges);
  compare(what, values, ref, n, 1e-9);
  free(ref);
}

static void cli_checks_armadillo(const char* mesh, const char* dir) {
  locus_session* s = NULL;
  const int64_t site_ids[6] = {0, 1000, 5000, 9000, 13000, 20000};
  locus_surface_point sites[6];
  double* d;
  double* ref = NULL;
  char* json;
  double num[64];
  int props = 0, k;
  int64_t nv, nv_ref;
  if (!call_ok(locus_session_create_from_file(mesh, &s), "locus_session_create_from_file")) return;
  nv = locus_session_vertex_count(s);
  d = malloc(sizeof(double) * 3 * (size_t)nv);
  if (!d) exit(1);
  for (k = 0; k < 6; ++k) {
    sites[k].face = -1;
    sites[k].vertex = site_ids[k];
  }

  /* Multi-source geodesic with one source = `locus geodesic --source 0`. */
  nv_ref = ply_vertex_doubles(ref_path(dir, "geodesic.ply"), &ref, &props);
  if (call_ok(locus_geodesic_distance_multi(s, sites, 1, d, NULL), "locus_geodesic_distance_multi") &&
      nv_ref == nv && props == 4) {
    double* col = malloc(sizeof(double) * (size_t)nv);
    int64_t i;
    if (!col) exit(1);
    for (i = 0; i < nv; ++i) col[i] = ref[4 * i + 3];
    compare("geodesic (one source)", d, col, nv, 1e-12);
    free(col);
  }
  free(ref);
  if (call_ok(locus_geodesic_distance_multi(s, sites, 6, d, NULL), "locus_geodesic_distance_multi (6 sources)")) {
    double lo = 1e300;
    for (k = 0; k < 6; ++k) lo = fmin(lo, d[site_ids[k]]);
    printf("  geodesic from 6 sources: smallest value at a source %.3g\n", lo);
    EXPECT(lo == 0.0, "the nearest source is not at distance 0");
  }

  /* Voronoi diagram: points and polylines of voronoi.obj, corner count of voronoi.json. */
  {
    int64_t max_points = 0, max_lines = 0, max_lp = 0, n_ref;
    locus_voronoi_output out;
    double* vref = NULL;
    locus_voronoi_bound(s, &max_points, &max_lines, &max_lp);
    memset(&out, 0, sizeof out);
    out.points = malloc(sizeof(double) * 3 * (size_t)max_points);
    out.points_capacity = max_points;
    if (!out.points) exit(1);
    if (call_ok(locus_voronoi(s, sites, 6, &out, NULL), "locus_voronoi")) {
      n_ref = obj_numbers(ref_path(dir, "voronoi.obj"), "v ", 3, &vref);
      EXPECT(n_ref == out.n_points, "voronoi: %lld points, the CLI has %lld", (long long)out.n_points, (long long)n_ref);
      if (n_ref == out.n_points) compare("voronoi points", out.points, vref, 3 * n_ref, 1e-12);
      json = read_text(ref_path(dir, "voronoi.json"));
      if (json_numbers(json, "polylines", num, 1) == 1)
        EXPECT(num[0] == (double)out.n_lines, "voronoi: %lld polylines, the CLI %g", (long long)out.n_lines, num[0]);
      free(json);
      free(vref);
    }
    free(out.points);
  }

  /* Voronoi diagram of 50 random surface points (seed 7) = `locus voronoi --random 50 --seed 7`. */
  {
    locus_surface_point random[50];
    int64_t max_points = 0, n_ref;
    locus_voronoi_output out;
    double* vref = NULL;
    locus_voronoi_bound(s, &max_points, NULL, NULL);
    memset(&out, 0, sizeof out);
    out.points = malloc(sizeof(double) * 3 * (size_t)max_points);
    out.points_capacity = max_points;
    if (!out.points) exit(1);
    if (call_ok(locus_random_surface_points(s, 50, 7, random), "locus_random_surface_points") &&
        call_ok(locus_voronoi(s, random, 50, &out, NULL), "locus_voronoi (random)")) {
      n_ref = obj_numbers(ref_path(dir, "voronoi_random.obj"), "v ", 3, &vref);
      EXPECT(n_ref == out.n_points, "voronoi (random): %lld points, the CLI has %lld", (long long)out.n_points,
             (long long)n_ref);
      if (n_ref == out.n_points) compare("voronoi points (50 random generators)", out.points, vref, 3 * n_ref, 1e-12);
      free(vref);
    }
    free(out.points);
  }

  /* Natural-neighbor coordinates of face 10 (0.2, 0.3, 0.5). */
  {
    locus_surface_point q;
    double w[6];
    q.face = 10;
    q.vertex = -1;
    q.bary[0] = 0.2;
    q.bary[1] = 0.3;
    q.bary[2] = 0.5;
    json = read_text(ref_path(dir, "nncoords.json"));
    if (call_ok(locus_nncoords(s, sites, 6, &q, w, NULL), "locus_nncoords") && json_numbers(json, "weights", num, 64) == 6)
      compare("natural-neighbor coordinates", w, num, 6, 1e-12);
    free(json);
  }

  /* ADF, HKS (1, 10, 100 h^2) and heat exchange. */
  {
    const int64_t v[3] = {0, 7, 12345};
    const double ts[3] = {1, 10, 100};
    const int64_t src[3] = {0, 1, 2}, tgt[3] = {100, 200, 25000};
    double out[9];
    json = read_text(ref_path(dir, "adf.json"));
    if (call_ok(locus_adf(s, v, 3, 0, out, NULL), "locus_adf") && json_numbers(json, "adf", num, 64) == 3)
      compare("auto-diffusion function", out, num, 3, 1e-12);
    free(json);
    json = read_text(ref_path(dir, "hks.json"));
    if (call_ok(locus_hks(s, ts, 3, v, 3, 0, out, NULL), "locus_hks") && json_numbers(json, "hks", num, 64) == 9)
      compare("heat kernel signature", out, num, 9, 1e-12);
    free(json);
    json = read_text(ref_path(dir, "heat.json"));
    if (call_ok(locus_heat_exchange(s, src, 3, tgt, 3, out, NULL), "locus_heat_exchange") &&
        json_numbers(json, "values", num, 64) == 3)
      compare("heat exchange", out, num, 3, 1e-12);
    free(json);
  }

  /* Deformation = deform.ply's positions. */
  {
    locus_deform_request r;
    memset(&r, 0, sizeof r);
    r.roi_seed = 0;
    r.roi_fraction = 0.1;
    r.handle_vertex = 0;
    r.handle_ring = 1;
    r.offset[0] = 0.5;
    r.offset[1] = 1;
    nv_ref = ply_vertex_doubles(ref_path(dir, "deform.ply"), &ref, &props);
    if (call_ok(locus_deform(s, &r, d, NULL), "locus_deform") && nv_ref == nv && props == 3)
      compare("deformation", d, ref, 3 * nv, 1e-9);
    free(ref);
  }

  /* Patch parameterizations (Neumann, circle) = the vt lines of the patch OBJs. */
  if (call_ok(locus_param_patch(s, 0, 0.1, 0, d, NULL, NULL, NULL), "locus_param_patch (Neumann)"))
    compare_patch_uv("patch parameterization (Neumann)", d, nv, ref_path(dir, "param_neumann.obj"));
  if (call_ok(locus_param_patch(s, 0, 0.1, 1, d, NULL, NULL, NULL), "locus_param_patch (circle)"))
    compare_patch_uv("patch parameterization (circle)", d, nv, ref_path(dir, "param_circle.obj"));
  free(d);
  locus_session_destroy(s);
}

/* The chapter-2 pipelines and skinning weights on patch.obj (a disk cut from armadillo). */
static void cli_checks_patch(const char* dir) {
  locus_session* s = NULL;
  double *uv, *xyz, *values, *ref = NULL;
  int32_t* edges;
  int32_t converged = 0;
  int64_t nv, ne, n_ref, i;
  int props = 0;
  if (!call_ok(locus_session_create_from_file(ref_path(dir, "patch.obj"), &s), "locus_session_create_from_file (patch)"))
    return;
  nv = locus_session_vertex_count(s);
  ne = locus_session_edge_count(s);
  printf("  patch.obj: %lld vertices, %lld edges\n", (long long)nv, (long long)ne);
  uv = malloc(sizeof(double) * 3 * (size_t)nv);
  xyz = malloc(sizeof(double) * 3 * (size_t)nv);
  values = malloc(sizeof(double) * (size_t)(ne > 3 * nv ? ne : 3 * nv));
  edges = malloc(sizeof(int32_t) * 2 * (size_t)ne);
  if (!uv || !xyz || !values || !edges) exit(1);

  if (call_ok(locus_param_disk(s, 0, 1000, 1e-6, uv, NULL, NULL), "locus_param_disk")) {
    n_ref = obj_numbers(ref_path(dir, "param_disk.obj"), "vt ", 2, &ref);
    if (n_ref == nv) compare("disk parameterization (perfect)", uv, ref, 2 * nv, 1e-9);
    else EXPECT(0, "param_disk.obj has %lld vt lines", (long long)n_ref);
    free(ref);
  }
  {
    const locus_surface_point h[3] = {{-1, 0, {1, 0, 0}}, {-1, 300, {1, 0, 0}}, {-1, 900, {1, 0, 0}}};
    double* w = malloc(sizeof(double) * 3 * (size_t)nv);
    if (!w) exit(1);
    n_ref = ply_vertex_doubles(ref_path(dir, "skinweights.ply"), &ref, &props);
    /* The weights are the last three properties (the patch's UVs, read from patch.obj's vt, come first). */
    if (call_ok(locus_skinning_weights(s, h, 3, w, NULL), "locus_skinning_weights") && n_ref == nv && props >= 6) {
      for (i = 0; i < nv; ++i) memcpy(xyz + 3 * i, ref + props * i + props - 3, 3 * sizeof(double));
      compare("skinning weights", w, xyz, 3 * nv, 1e-12);
    }
    free(ref);
    free(w);
  }
  if (call_ok(locus_perfect_laplacian(s, 0, 20, 1e-6, edges, values, xyz, &converged, NULL), "locus_perfect_laplacian")) {
    compare_edge_file("perfect Laplacian weights", ref_path(dir, "perfect_laplacian.obj.weights.txt"), edges, values, ne);
    n_ref = obj_numbers(ref_path(dir, "perfect_laplacian.obj"), "v ", 3, &ref);
    if (n_ref == nv) compare("perfect Laplacian embedding", xyz, ref, 3 * nv, 1e-9);
    free(ref);
  }
  if (call_ok(locus_self_supporting(s, 1.0, 20, 1e-6, edges, values, xyz, &converged, NULL), "locus_self_supporting")) {
    compare_edge_file("self-supporting forces", ref_path(dir, "selfsupport.obj.forces.txt"), edges, values, ne);
    n_ref = obj_numbers(ref_path(dir, "selfsupport.obj"), "v ", 3, &ref);
    if (n_ref == nv) compare("self-supporting surface", xyz, ref, 3 * nv, 1e-9);
    free(ref);
  }
  free(uv);
  free(xyz);
  free(values);
  free(edges);
  locus_session_destroy(s);
}


int main(int argc, char** argv) {
  int32_t major = 0, minor = 0, patch = 0;
  printf("locus %s (header %d.%d.%d)\n", locus_version(&major, &minor, &patch), LOCUS_VERSION_MAJOR,
         LOCUS_VERSION_MINOR, LOCUS_VERSION_PATCH);
  EXPECT(major == LOCUS_VERSION_MAJOR && minor == LOCUS_VERSION_MINOR, "version mismatch");
  /* The package's version (find_package's locus_VERSION or pkg-config --modversion) is the library's. */
  EXPECT(strcmp(locus_version(NULL, NULL, NULL), LOCUS_VERSION_STRING) == 0, "library vs header version string");
  EXPECT(strcmp(locus_version(NULL, NULL, NULL), LOCUS_PACKAGE_VERSION) == 0, "library %s vs package version %s",
         locus_version(NULL, NULL, NULL), LOCUS_PACKAGE_VERSION);
  sphere_checks(4);
  if (argc > 1) file_checks(argv[1]);
  if (argc > 1 && getenv("LOCUS_PACKAGE_REFS")) {
    printf("every pipeline against the CLI (%s):\n", getenv("LOCUS_PACKAGE_REFS"));
    cli_checks_armadillo(argv[1], getenv("LOCUS_PACKAGE_REFS"));
    cli_checks_patch(getenv("LOCUS_PACKAGE_REFS"));
  }
  if (failures) {
    fprintf(stderr, "%d check(s) failed\n", failures);
    return 1;
  }
  printf("all checks passed\n");
  return 0;
}
