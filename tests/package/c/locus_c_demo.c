/* A C program that uses only <locus/locus.h>, built against the installed
 * package (tests/package/run_package_test.cmake). With a mesh path argument it
 * creates a session from that file (armadillo in the test), computes a heat
 * geodesic distance, a log map and a 100-site CVT, prints the figures and
 * checks that they are sane; it always also builds a session from arrays (an
 * octahedron refined to a sphere) and checks distances against great circles.
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
  if (failures) {
    fprintf(stderr, "%d check(s) failed\n", failures);
    return 1;
  }
  printf("all checks passed\n");
  return 0;
}
