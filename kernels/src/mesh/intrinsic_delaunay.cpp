// Intrinsic Delaunay flips (Bobenko & Springborn, "A discrete Laplace-Beltrami
// operator for simplicial surfaces", 2007; Sharp & Crane SGP 2020 §4.3), on the
// flat side arrays of intrinsic_triangulation.hpp. A flip rewrites the two faces
// of an edge in place (their six slots), so no face or side is ever allocated.
#include "locus/kernels/mesh/intrinsic_delaunay.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace locus {

namespace {

// cot of the two angles opposite edge s (one per face): Delaunay when >= 0.
double cotan_sum(const IntrinsicTriangulation& T, int32_t s) {
  return cotan_opposite(T, s) + cotan_opposite(T, T.twin[s]);
}

// Length of the other diagonal of the quad made by the faces of s (i -> j, apex k)
// and of its twin (j -> i, apex l): both triangles laid out in the plane on the
// segment i j, k above and l below.
double flipped_length(const IntrinsicTriangulation& T, int32_t s) {
  const int32_t t = T.twin[s];
  const double lij = T.length[s];
  const double ljk = T.length[side_next(s)], lki = T.length[side_prev(s)];
  const double lil = T.length[side_next(t)], llj = T.length[side_prev(t)];
  const double xk = (lij * lij + lki * lki - ljk * ljk) / (2.0 * lij);
  const double yk = 2.0 * intrinsic_triangle_area(lij, ljk, lki) / lij;
  const double xl = (lij * lij + lil * lil - llj * llj) / (2.0 * lij);
  const double yl = 2.0 * intrinsic_triangle_area(lij, lil, llj) / lij;
  return std::hypot(xk - xl, yk + yl);
}

// Replaces edge i-j (side s in face A = (i, j, k), twin t in face B = (j, i, l))
// by k-l: A becomes (l, k, i), B becomes (k, l, j). The outer sides move to new
// slots; their twins are pointed at them. Returns false (nothing changed) when an
// outer side is glued to the other face of the quad.
bool flip(IntrinsicTriangulation& T, int32_t s) {
  const int32_t t = T.twin[s];
  const int32_t fa = s / 3, fb = t / 3;
  if (fa == fb) return false;
  const int32_t outer[4] = {side_prev(s), side_next(t), side_prev(t), side_next(s)};  // k->i, i->l, l->j, j->k
  for (const int32_t o : outer)
    if (T.twin[o] / 3 == fa || T.twin[o] / 3 == fb) return false;
  const double diag = flipped_length(T, s);
  if (!(diag > 0.0) || !std::isfinite(diag)) return false;
  const int32_t i = T.vertex[s], j = T.vertex[t];
  const int32_t k = T.vertex[side_prev(s)], l = T.vertex[side_prev(t)];
  int32_t otwin[4];
  double olen[4];
  for (int q = 0; q < 4; ++q) {
    otwin[q] = T.twin[outer[q]];
    olen[q] = T.length[outer[q]];
  }
  const int32_t a0 = 3 * fa, b0 = 3 * fb;
  // New slots: A = (l->k, k->i, i->l), B = (k->l, l->j, j->k).
  const int32_t slot[4] = {a0 + 1, a0 + 2, b0 + 1, b0 + 2};
  const int32_t tail[4] = {k, i, l, j};
  T.vertex[a0] = l;
  T.vertex[b0] = k;
  T.twin[a0] = b0;
  T.twin[b0] = a0;
  T.length[a0] = T.length[b0] = diag;
  for (int q = 0; q < 4; ++q) {
    T.vertex[slot[q]] = tail[q];
    T.length[slot[q]] = olen[q];
    T.twin[slot[q]] = otwin[q];
    T.twin[otwin[q]] = slot[q];
  }
  return true;
}

}  // namespace

DelaunayFlipStats flip_to_intrinsic_delaunay(IntrinsicTriangulation& T) {
  const int32_t ns = static_cast<int32_t>(T.vertex.size());
  DelaunayFlipStats st;
  const int64_t budget = 50 * static_cast<int64_t>(ns) + 1000;
  std::vector<int32_t> queue;
  std::vector<char> queued(static_cast<size_t>(ns), 0);
  queue.reserve(static_cast<size_t>(ns / 2));
  for (int32_t s = ns - 1; s >= 0; --s)
    if (s < T.twin[s]) {
      queue.push_back(s);
      queued[s] = 1;
    }
  while (!queue.empty()) {
    const int32_t s = queue.back();
    queue.pop_back();
    queued[s] = 0;
    if (!(cotan_sum(T, s) < -kDelaunayTolerance)) continue;
    if (st.flips >= budget) {
      st.converged = false;
      break;
    }
    const int32_t a0 = 3 * (s / 3), b0 = 3 * (T.twin[s] / 3);
    if (!flip(T, s)) continue;
    ++st.flips;
    // The four outer edges may have lost the Delaunay property.
    for (const int32_t o : {a0 + 1, a0 + 2, b0 + 1, b0 + 2})
      if (!queued[o]) {
        queued[o] = 1;
        queue.push_back(o);
      }
  }
  return st;
}

}  // namespace locus
