// Exact incremental 3D convex hull with conflict lists (see convex_hull.hpp).
//
// Data are flat arrays: per face three vertices, three neighbors (neighbor k is
// across the edge fv[k] -> fv[k+1]), an alive flag and the head of its conflict
// list; per point the next point in the same list and the face it is filed under.
// When a point p is inserted, the points filed under the faces p sees are filed
// again under one of the new faces around p, or dropped: a point outside the new
// hull that saw a deleted face f must see one of the new faces (the segment from it
// to the interior of f leaves the new hull through a new face), so nothing else
// needs to be searched.
#include "locus/kernels/mesh/convex_hull.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <climits>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/morton_order.hpp"

namespace locus {

namespace {

using i128 = __int128;
using u128 = unsigned __int128;

// |m| * |d| as three 64-bit limbs (|m| < 2^108, |d| < 2^54 here, so < 2^162).
struct U192 {
  uint64_t w[3] = {0, 0, 0};
};

U192 mul_abs(i128 m, int64_t d) {
  const u128 am = m < 0 ? static_cast<u128>(-m) : static_cast<u128>(m);
  const uint64_t ad = d < 0 ? static_cast<uint64_t>(-d) : static_cast<uint64_t>(d);
  const u128 p0 = static_cast<u128>(static_cast<uint64_t>(am)) * ad;
  const u128 p1 = static_cast<u128>(static_cast<uint64_t>(am >> 64)) * ad;
  const u128 t = (p0 >> 64) + static_cast<uint64_t>(p1);
  U192 r;
  r.w[0] = static_cast<uint64_t>(p0);
  r.w[1] = static_cast<uint64_t>(t);
  r.w[2] = static_cast<uint64_t>(t >> 64) + static_cast<uint64_t>(p1 >> 64);
  return r;
}

void add_to(U192& acc, const U192& v) {
  u128 carry = 0;
  for (int k = 0; k < 3; ++k) {
    const u128 s = static_cast<u128>(acc.w[k]) + v.w[k] + carry;
    acc.w[k] = static_cast<uint64_t>(s);
    carry = s >> 64;
  }
}

int compare(const U192& a, const U192& b) {
  for (int k = 2; k >= 0; --k)
    if (a.w[k] != b.w[k]) return a.w[k] < b.w[k] ? -1 : 1;
  return 0;
}

}  // namespace

int orient3d_exact(const int64_t a[3], const int64_t b[3], const int64_t c[3], const int64_t d[3]) {
  const int64_t bx = b[0] - a[0], by = b[1] - a[1], bz = b[2] - a[2];
  const int64_t cx = c[0] - a[0], cy = c[1] - a[1], cz = c[2] - a[2];
  const int64_t dx = d[0] - a[0], dy = d[1] - a[1], dz = d[2] - a[2];
  // Filter: the differences are exact in double; only the 14 products and sums round.
  // 1e-15 * permanent exceeds the rounding error bound (about 7.8e-16 * permanent).
  {
    const double fbx = double(bx), fby = double(by), fbz = double(bz);
    const double fcx = double(cx), fcy = double(cy), fcz = double(cz);
    const double fdx = double(dx), fdy = double(dy), fdz = double(dz);
    const double m1 = fcy * fdz - fcz * fdy, m2 = fcx * fdz - fcz * fdx, m3 = fcx * fdy - fcy * fdx;
    const double det = fbx * m1 - fby * m2 + fbz * m3;
    const double perm = std::fabs(fbx) * (std::fabs(fcy * fdz) + std::fabs(fcz * fdy)) +
                        std::fabs(fby) * (std::fabs(fcx * fdz) + std::fabs(fcz * fdx)) +
                        std::fabs(fbz) * (std::fabs(fcx * fdy) + std::fabs(fcy * fdx));
    const double bound = 1e-15 * perm;
    if (det > bound) return 1;
    if (det < -bound) return -1;
  }
  // Exact: 2x2 minors fit in 128 bits (< 2^107), the products in 192 bits.
  const i128 m1 = i128(cy) * dz - i128(cz) * dy;
  const i128 m2 = i128(cx) * dz - i128(cz) * dx;
  const i128 m3 = i128(cx) * dy - i128(cy) * dx;
  U192 pos, neg;
  auto accumulate = [&](int64_t s, i128 m, bool negate) {
    if (s == 0 || m == 0) return;
    const bool negative = ((s < 0) != (m < 0)) != negate;
    add_to(negative ? neg : pos, mul_abs(m, s));
  };
  accumulate(bx, m1, false);
  accumulate(by, m2, true);
  accumulate(bz, m3, false);
  return compare(pos, neg);
}

namespace {

// Checked copy of the input as flat (x, y, z) triples.
std::vector<int64_t> load_points(std::span<const int64_t> X, std::span<const int64_t> Y, std::span<const int64_t> Z) {
  if (X.size() != Y.size() || X.size() != Z.size())
    fail(ErrorCode::BadUsage, "convex_hull_3d: coordinate arrays differ in length");
  if (X.size() > static_cast<size_t>(INT32_MAX / 8))
    fail(ErrorCode::ResourceLimit, "convex_hull_3d: too many points (" + std::to_string(X.size()) + ")");
  const int32_t n = static_cast<int32_t>(X.size());
  if (n < 4) fail(ErrorCode::BadInput, "convex_hull_3d: need at least 4 points, got " + std::to_string(n));
  std::vector<int64_t> P(3 * static_cast<size_t>(n));
  for (int32_t i = 0; i < n; ++i) {
    const int64_t c[3] = {X[i], Y[i], Z[i]};
    for (int k = 0; k < 3; ++k) {
      if (c[k] > kConvexHullMaxCoordinate || c[k] < -kConvexHullMaxCoordinate)
        fail(ErrorCode::BadInput, "convex_hull_3d: point " + std::to_string(i) + " has a coordinate beyond 2^52");
      P[3 * static_cast<size_t>(i) + k] = c[k];
    }
  }
  return P;
}

// Initial tetrahedron from the first points in general position (input
// indices), ordered so that s[3] lies below the plane of (s0, s1, s2).
std::array<int32_t, 4> initial_simplex(const std::vector<int64_t>& P, int32_t n) {
  auto pt = [&](int32_t i) { return P.data() + 3 * static_cast<size_t>(i); };
  std::array<int32_t, 4> s = {0, -1, -1, -1};
  for (int32_t i = 1; i < n && s[1] < 0; ++i)
    if (pt(i)[0] != pt(0)[0] || pt(i)[1] != pt(0)[1] || pt(i)[2] != pt(0)[2]) s[1] = i;
  if (s[1] >= 0) {
    const int64_t* a = pt(s[0]);
    const int64_t* b = pt(s[1]);
    for (int32_t i = s[1] + 1; i < n && s[2] < 0; ++i) {
      const int64_t* c = pt(i);
      const i128 ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
      const i128 wx = c[0] - a[0], wy = c[1] - a[1], wz = c[2] - a[2];
      if (uy * wz - uz * wy != 0 || uz * wx - ux * wz != 0 || ux * wy - uy * wx != 0) s[2] = i;
    }
  }
  if (s[2] >= 0)
    for (int32_t i = s[2] + 1; i < n && s[3] < 0; ++i)
      if (orient3d_exact(pt(s[0]), pt(s[1]), pt(s[2]), pt(i)) != 0) s[3] = i;
  if (s[3] < 0) fail(ErrorCode::BadInput, "convex_hull_3d: all " + std::to_string(n) + " points are coplanar");
  if (orient3d_exact(pt(s[0]), pt(s[1]), pt(s[2]), pt(s[3])) > 0) std::swap(s[1], s[2]);
  return s;
}

// Insertion follows the input order, but the points are stored in Morton (Z-curve)
// order: the points re-filed together after an insertion are spatially close, and
// now also close in memory. Halves the running time on large inputs (cache misses
// dominated). Reorders P; `orig` maps storage position to input index, `internal`
// the reverse.
void sort_morton(std::vector<int64_t>& P, int32_t n, std::vector<int32_t>& orig, std::vector<int32_t>& internal) {
  // Codes from the top 21 of the 53 bits of each shifted coordinate.
  std::vector<uint64_t> code(static_cast<size_t>(n));
  for (int32_t i = 0; i < n; ++i) {
    const int64_t* c = P.data() + 3 * static_cast<size_t>(i);
    uint64_t q[3];
    for (int d = 0; d < 3; ++d) q[d] = static_cast<uint64_t>(c[d] + kConvexHullMaxCoordinate) >> 32;
    code[static_cast<size_t>(i)] = morton_code(q[0], q[1], q[2]);
  }
  orig.resize(static_cast<size_t>(n));
  internal.resize(static_cast<size_t>(n));
  MortonWorkspace ws;
  morton_order(code, orig, ws);
  std::vector<int64_t> sorted(P.size());
  for (int32_t k = 0; k < n; ++k) {
    internal[orig[k]] = k;
    for (int d = 0; d < 3; ++d) sorted[3 * static_cast<size_t>(k) + d] = P[3 * static_cast<size_t>(orig[k]) + d];
  }
  P.swap(sorted);
}

// The incremental construction on points in storage order: faces, their
// neighbors and conflict lists (the data layout of the file comment).
class HullBuilder {
 public:
  HullBuilder(std::vector<int64_t> P, int32_t n)
      : P_(std::move(P)), n_(n), next_point_(static_cast<size_t>(n), -1), conflict_(static_cast<size_t>(n), -1),
        new_face_from_(static_cast<size_t>(n), -1) {}

  // The tetrahedron s (storage indices, oriented as initial_simplex returns it)
  // and every other point filed under the first of its faces it sees.
  void start(const std::array<int32_t, 4>& s);
  // Inserts point p (storage index) if it lies outside the current hull.
  void insert(int32_t p);
  // Triangles of the alive faces, vertices mapped through orig.
  std::vector<int32_t> triangles(const std::vector<int32_t>& orig) const;

 private:
  struct HorizonEdge {
    int32_t u, w, outside;
  };
  const int64_t* pt(int32_t i) const { return P_.data() + 3 * static_cast<size_t>(i); }
  int32_t new_face(int32_t a, int32_t b, int32_t c);
  bool sees(int32_t f, int32_t q) const;
  void file_under(int32_t q, int32_t f) {
    conflict_[q] = f;
    next_point_[q] = head_[f];
    head_[f] = q;
  }
  void find_visible(int32_t p, int32_t f0);
  void cone_horizon(int32_t p);
  void refile_points(int32_t p);

  std::vector<int64_t> P_;
  int32_t n_;
  std::vector<int32_t> fv_, nb_, head_, stamp_;
  std::vector<char> alive_;
  // Per face a rounded normal and the coefficients of the permanent, so that most
  // visibility tests cost one dot product. n_k = u_i w_j - u_j w_i is off by at most
  // 2 eps (|u_i w_j| + |u_j w_i|) = 2 eps perm_k; with the dot product's own rounding
  // the error of n . (q - a) stays below 5 eps sum_k perm_k |q_k - a_k| (5 eps = 5.6e-16),
  // so 2e-15 times that sum is a safe filter; anything closer is decided exactly.
  std::vector<double> plane_;  // 6 per face: n, perm
  std::vector<int32_t> next_point_, conflict_;
  std::vector<int32_t> visible_, created_, new_face_from_;
  std::vector<HorizonEdge> horizon_;
};

int32_t HullBuilder::new_face(int32_t a, int32_t b, int32_t c) {
  const int32_t f = static_cast<int32_t>(alive_.size());
  fv_.insert(fv_.end(), {a, b, c});
  nb_.insert(nb_.end(), {-1, -1, -1});
  alive_.push_back(1);
  head_.push_back(-1);
  stamp_.push_back(-1);
  const int64_t *pa = pt(a), *pb = pt(b), *pc = pt(c);
  const double ux = double(pb[0] - pa[0]), uy = double(pb[1] - pa[1]), uz = double(pb[2] - pa[2]);
  const double wx = double(pc[0] - pa[0]), wy = double(pc[1] - pa[1]), wz = double(pc[2] - pa[2]);
  plane_.insert(plane_.end(), {uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx,
                               std::fabs(uy * wz) + std::fabs(uz * wy), std::fabs(uz * wx) + std::fabs(ux * wz),
                               std::fabs(ux * wy) + std::fabs(uy * wx)});
  return f;
}

bool HullBuilder::sees(int32_t f, int32_t q) const {
  const int64_t* a = pt(fv_[3 * f]);
  const int64_t* p = pt(q);
  const double dx = double(p[0] - a[0]), dy = double(p[1] - a[1]), dz = double(p[2] - a[2]);
  const double* pl = plane_.data() + 6 * static_cast<size_t>(f);
  const double det = pl[0] * dx + pl[1] * dy + pl[2] * dz;
  const double bound = 2e-15 * (pl[3] * std::fabs(dx) + pl[4] * std::fabs(dy) + pl[5] * std::fabs(dz));
  if (det > bound) return true;
  if (det < -bound) return false;
  return orient3d_exact(a, pt(fv_[3 * f + 1]), pt(fv_[3 * f + 2]), p) > 0;
}

void HullBuilder::start(const std::array<int32_t, 4>& s) {
  // s[3] lies below (s0, s1, s2); these four faces then all face outward.
  new_face(s[0], s[1], s[2]);
  new_face(s[0], s[3], s[1]);
  new_face(s[1], s[3], s[2]);
  new_face(s[2], s[3], s[0]);
  for (int32_t f = 0; f < 4; ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t u = fv_[3 * f + k], w = fv_[3 * f + (k + 1) % 3];
      for (int32_t g = 0; g < 4; ++g)
        for (int l = 0; l < 3; ++l)
          if (fv_[3 * g + l] == w && fv_[3 * g + (l + 1) % 3] == u) nb_[3 * f + k] = g;
    }
  for (int32_t q = 0; q < n_; ++q) {
    if (q == s[0] || q == s[1] || q == s[2] || q == s[3]) continue;
    for (int32_t f = 0; f < 4; ++f)
      if (sees(f, q)) {
        file_under(q, f);
        break;
      }
  }
}

// Visible faces: the region around f0 whose planes have p strictly above, and
// the horizon edges around it. stamp = 2p marks visible, 2p + 1 tested and not visible.
void HullBuilder::find_visible(int32_t p, int32_t f0) {
  visible_.assign(1, f0);
  stamp_[f0] = 2 * p;
  horizon_.clear();
  for (size_t i = 0; i < visible_.size(); ++i) {
    const int32_t f = visible_[i];
    for (int k = 0; k < 3; ++k) {
      const int32_t g = nb_[3 * f + k];
      if (stamp_[g] != 2 * p && stamp_[g] != 2 * p + 1) {
        if (sees(g, p)) {
          stamp_[g] = 2 * p;
          visible_.push_back(g);
        } else {
          stamp_[g] = 2 * p + 1;
        }
      }
      if (stamp_[g] == 2 * p + 1) horizon_.push_back({fv_[3 * f + k], fv_[3 * f + (k + 1) % 3], g});
    }
  }
}

// Cone the horizon to p; new face (u, w, p) keeps the orientation of the deleted face.
void HullBuilder::cone_horizon(int32_t p) {
  created_.clear();
  for (const HorizonEdge& h : horizon_) {
    const int32_t F = new_face(h.u, h.w, p);
    created_.push_back(F);
    nb_[3 * F] = h.outside;
    for (int l = 0; l < 3; ++l)
      if (fv_[3 * h.outside + l] == h.w && fv_[3 * h.outside + (l + 1) % 3] == h.u) nb_[3 * h.outside + l] = F;
    new_face_from_[h.u] = F;
  }
  for (const int32_t F : created_) {
    const int32_t G = new_face_from_[fv_[3 * F + 1]];  // the new face on edge (w, p)
    // The visible region of a convex polytope is a disc, so its horizon is one cycle.
    if (G < 0) fail(ErrorCode::Internal, "convex_hull_3d: horizon is not a cycle at point " + std::to_string(p));
    nb_[3 * F + 1] = G;
    nb_[3 * G + 2] = F;
  }
  for (const HorizonEdge& h : horizon_) new_face_from_[h.u] = -1;
}

// Re-file the points of the deleted (visible) faces under the new faces.
void HullBuilder::refile_points(int32_t p) {
  for (const int32_t f : visible_) {
    alive_[f] = 0;
    for (int32_t q = head_[f]; q >= 0;) {
      const int32_t after = next_point_[q];
      conflict_[q] = -1;
      if (q != p)
        for (const int32_t F : created_)
          if (sees(F, q)) {
            file_under(q, F);
            break;
          }
      q = after;
    }
    head_[f] = -1;
  }
}

void HullBuilder::insert(int32_t p) {
  const int32_t f0 = conflict_[p];
  if (f0 < 0) return;  // inside the hull (or a simplex vertex)
  find_visible(p, f0);
  cone_horizon(p);
  refile_points(p);
}

std::vector<int32_t> HullBuilder::triangles(const std::vector<int32_t>& orig) const {
  std::vector<int32_t> tri;
  for (size_t f = 0; f < alive_.size(); ++f)
    if (alive_[f]) tri.insert(tri.end(), {orig[fv_[3 * f]], orig[fv_[3 * f + 1]], orig[fv_[3 * f + 2]]});
  return tri;
}

}  // namespace

std::vector<int32_t> convex_hull_3d(std::span<const int64_t> X, std::span<const int64_t> Y,
                                    std::span<const int64_t> Z) {
  std::vector<int64_t> P = load_points(X, Y, Z);
  const int32_t n = static_cast<int32_t>(X.size());
  std::array<int32_t, 4> s = initial_simplex(P, n);
  std::vector<int32_t> orig, internal;
  sort_morton(P, n, orig, internal);
  for (int32_t& v : s) v = internal[v];
  HullBuilder hull(std::move(P), n);
  hull.start(s);
  for (int32_t i = 0; i < n; ++i) hull.insert(internal[i]);
  return hull.triangles(orig);
}

}  // namespace locus
