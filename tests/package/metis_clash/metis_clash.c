/* A host that defines METIS_NodeND and gk_malloc itself (as a program linking
 * its own METIS does) and uses locus, whose ordering runs METIS internally.
 * It must link against liblocus.a and liblocus.so without "multiple
 * definition", locus must keep calling its own METIS (the host's functions
 * are never entered by locus), and the host's calls reach the host's code.
 * The geodesic distance on a flat grid is checked against the straight line. */
#include <locus/locus.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static int host_metis_calls = 0;

int METIS_NodeND(int32_t* nvtxs, int32_t* xadj, int32_t* adjncy, int32_t* vwgt, int32_t* options, int32_t* perm,
                 int32_t* iperm) {
  (void)xadj, (void)adjncy, (void)vwgt, (void)options;
  for (int32_t i = 0; i < *nvtxs; ++i) perm[i] = iperm[i] = i;
  ++host_metis_calls;
  return 1;
}

void* gk_malloc(size_t n, char* msg) {
  (void)msg;
  ++host_metis_calls;
  return malloc(n);
}

int main(void) {
  enum { N = 160 }; /* 25,600 vertices: locus orders this with nested dissection */
  const int64_t nv = (int64_t)N * N, nf = 2 * (int64_t)(N - 1) * (N - 1);
  double* xyz = malloc(sizeof(double) * 3 * (size_t)nv);
  int32_t* tris = malloc(sizeof(int32_t) * 3 * (size_t)nf);
  double* d = malloc(sizeof(double) * (size_t)nv);
  if (!xyz || !tris || !d) return 1;
  const double h = 1.0 / (N - 1);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      double* p = xyz + 3 * (i * N + j);
      p[0] = j * h, p[1] = i * h, p[2] = 0.0;
    }
  int64_t f = 0;
  for (int i = 0; i + 1 < N; ++i)
    for (int j = 0; j + 1 < N; ++j) {
      const int32_t a = i * N + j, b = a + 1, c = a + N, e = c + 1;
      int32_t* t = tris + 3 * f;
      t[0] = a, t[1] = b, t[2] = e, t[3] = a, t[4] = e, t[5] = c;
      f += 2;
    }
  locus_session* s = NULL;
  if (locus_session_create(xyz, nv, tris, nf, &s) != LOCUS_OK) {
    fprintf(stderr, "metis_clash: locus_session_create failed\n");
    return 1;
  }
  const int32_t centre = (N / 2) * N + N / 2;
  const locus_status st = locus_geodesic_distance(s, centre, d);
  locus_session_destroy(s);
  if (st != LOCUS_OK) {
    fprintf(stderr, "metis_clash: locus_geodesic_distance failed (%d)\n", (int)st);
    return 1;
  }
  /* A point a quarter of the side away along a row: the straight line. */
  const double got = d[centre + N / 4], want = (N / 4) * h;
  if (fabs(got - want) > 0.05 * want) {
    fprintf(stderr, "metis_clash: distance %.6f, straight line %.6f\n", got, want);
    return 1;
  }
  if (host_metis_calls != 0) {
    fprintf(stderr, "metis_clash: locus called the host's METIS (%d calls)\n", host_metis_calls);
    return 1;
  }
  int32_t n = 3, xadj[4] = {0, 1, 3, 4}, adj[4] = {1, 0, 2, 1}, perm[3], iperm[3];
  METIS_NodeND(&n, xadj, adj, NULL, NULL, perm, iperm);
  if (host_metis_calls != 1) {
    fprintf(stderr, "metis_clash: the host's own METIS_NodeND was not called\n");
    return 1;
  }
  printf("metis_clash: the host's METIS and locus' coexist (distance %.5f, line %.5f)\n", got, want);
  free(xyz), free(tris), free(d);
  return 0;
}
