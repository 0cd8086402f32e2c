// The remesh pulled towards its input's farthest vertices
// (pipelines/include/locus/pipelines/voronoi/remesh_fidelity.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_fidelity.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "remesh_vec3.hpp"

namespace locus {

namespace {

using namespace remesh_vec3;

// Vertex -> items (CSR).
struct Csr {
  std::vector<int64_t> off;
  std::vector<int32_t> item;
};
template <class Each>
Csr make_csr(int32_t n, int32_t items, const Each& each) {
  Csr c;
  c.off.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t i = 0; i < items; ++i) each(i, [&](int32_t v) { ++c.off[v + 1]; });
  for (int32_t v = 0; v < n; ++v) c.off[v + 1] += c.off[v];
  c.item.resize(static_cast<size_t>(c.off[n]));
  std::vector<int64_t> fill(c.off.begin(), c.off.end() - 1);
  for (int32_t i = 0; i < items; ++i) each(i, [&](int32_t v) { c.item[fill[v]++] = i; });
  return c;
}

struct Pass {
  const Mesh& input;
  const TriangleGrid& grid;
  Mesh& m;
  const std::vector<std::array<int32_t, 3>>& F;
  const Csr& vf;      // remesh vertex -> its triangles
  const Csr& owned;   // remesh vertex -> input vertices whose nearest remesh triangle holds it
  double keep;        // radians

  V3 at(int32_t w, int32_t v, const V3& p) const { return w == v ? p : pos(m, w); }

  // The triangles around v (v's and its neighbors') and the input vertices
  // whose nearest remesh triangle is one of v's.
  void neighborhood(int32_t v, std::vector<int32_t>& faces, std::vector<int32_t>& near) const {
    faces.clear();
    near.clear();
    std::vector<int32_t> verts;
    for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q)
      for (int32_t w : F[vf.item[q]]) verts.push_back(w);
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    for (int32_t w : verts)
      for (int64_t q = vf.off[w]; q < vf.off[w + 1]; ++q) faces.push_back(vf.item[q]);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    // Only the input vertices nearest to a triangle of v can get farther: any
    // other keeps its nearest triangle, which v's move does not touch.
    for (int64_t q = owned.off[v]; q < owned.off[v + 1]; ++q) near.push_back(owned.item[q]);
  }

  // The local two-sided distance with v at p.
  double local_error(int32_t v, const V3& p, const std::vector<int32_t>& faces, const std::vector<int32_t>& near) const {
    double e = 0;
    for (int32_t i : near) {
      const V3 x = pos(input, i);
      double best = HUGE_VAL;
      for (int32_t f : faces) {
        const auto& t = F[f];
        const V3 c = closest_point_on_triangle(x, at(t[0], v, p), at(t[1], v, p), at(t[2], v, p));
        best = std::min(best, norm(sub(c, x)));
      }
      e = std::max(e, best);
    }
    for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
      const auto& t = F[vf.item[q]];
      V3 c = {0, 0, 0};
      for (int32_t w : t) {
        const V3 pw = at(w, v, p);
        for (int k = 0; k < 3; ++k) c[k] += pw[k] / 3;
        if (w == v) continue;
        e = std::max(e, grid.distance({0.5 * (p[0] + pw[0]), 0.5 * (p[1] + pw[1]), 0.5 * (p[2] + pw[2])}));
      }
      e = std::max(e, grid.distance(c));
    }
    return e;
  }

  // v's ring with v at p: no triangle turned more than 60 degrees, none below
  // min(the ring's smallest angle, keep).
  bool ring_ok(int32_t v, const V3& p, double floor, double& new_sum) const {
    double sum = 0;
    for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
      const auto& t = F[vf.item[q]];
      const V3 a0 = pos(m, t[0]), a1 = pos(m, t[1]), a2 = pos(m, t[2]);
      const V3 b0 = at(t[0], v, p), b1 = at(t[1], v, p), b2 = at(t[2], v, p);
      const V3 n0 = tri_normal(a0, a1, a2), n1 = tri_normal(b0, b1, b2);
      if (!(dot(n0, n1) > 0.5 * norm(n0) * norm(n1))) return false;
      const double a = min_angle(b0, b1, b2);
      if (a < floor) return false;
      sum += a;
    }
    new_sum = sum;
    return true;
  }

  double ring_min(int32_t v, double& sum) const {
    double r = M_PI;
    sum = 0;
    for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
      const auto& t = F[vf.item[q]];
      const double a = min_angle(pos(m, t[0]), pos(m, t[1]), pos(m, t[2]));
      r = std::min(r, a);
      sum += a;
    }
    return r;
  }

  // After v moved: the input vertices whose nearest triangle touches v's
  // ring, against the triangles around v (which hold that triangle).
  void refresh(int32_t v, std::vector<ClosestPoint>& cp, std::vector<int32_t>& faces) const {
    std::vector<int32_t> near;
    neighborhood(v, faces, near);
    std::vector<int32_t> pts;
    for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q)
      for (int32_t w : F[vf.item[q]])
        for (int64_t r = owned.off[w]; r < owned.off[w + 1]; ++r) pts.push_back(owned.item[r]);
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    for (int32_t i : pts) {
      const V3 x = pos(input, i);
      ClosestPoint best;
      best.distance = HUGE_VAL;
      for (int32_t f : faces) {
        const auto& t = F[f];
        const V3 c = closest_point_on_triangle(x, pos(m, t[0]), pos(m, t[1]), pos(m, t[2]));
        const double d = norm(sub(c, x));
        if (d < best.distance) best = {c, f, d};
      }
      cp[i] = best;
    }
  }

  // v pulled towards input vertex i; true when a move was kept.
  bool pull(int32_t v, int32_t i, std::vector<int32_t>& faces, std::vector<int32_t>& near, double& budget) const {
    neighborhood(v, faces, near);
    const V3 p0 = pos(m, v), target = pos(input, i);
    const double before = local_error(v, p0, faces, near);
    double sum = 0;
    const double floor = std::min(ring_min(v, sum), keep) - 1e-9;
    V3 nv{0, 0, 0};
    for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
      const auto& t = F[vf.item[q]];
      const V3 nn = tri_normal(pos(m, t[0]), pos(m, t[1]), pos(m, t[2]));
      for (int k = 0; k < 3; ++k) nv[k] += nn[k];
    }
    for (double s : {1.0, 0.75, 0.5, 0.25, 0.125}) {
      const ClosestPoint cp = grid.closest({p0[0] + s * (target[0] - p0[0]), p0[1] + s * (target[1] - p0[1]),
                                            p0[2] + s * (target[2] - p0[2])});
      if (cp.face < 0) continue;
      const auto fv = input.face(cp.face);
      const V3 ni = tri_normal(pos(input, fv[0]), pos(input, fv[1]), pos(input, fv[2]));
      if (!(dot(ni, nv) > 0.5 * norm(ni) * norm(nv))) continue;
      double new_sum = 0;
      if (!ring_ok(v, cp.point, floor, new_sum) || sum - new_sum > budget) continue;
      if (local_error(v, cp.point, faces, near) < before * (1 - 1e-6)) {
        m.x[v] = cp.point[0];
        m.y[v] = cp.point[1];
        m.z[v] = cp.point[2];
        budget -= std::max(0.0, sum - new_sum);
        return true;
      }
    }
    return false;
  }
};

}  // namespace

int64_t pull_to_input(const Mesh& input, const TriangleGrid& grid, Mesh& remesh, const RemeshFidelityOptions& opt) {
  if (!remesh.is_triangle_mesh() || remesh.num_faces() == 0 || input.num_vertices() == 0) return 0;
  const int32_t n = remesh.num_vertices(), ni = input.num_vertices();
  std::vector<std::array<int32_t, 3>> F(remesh.num_faces());
  for (int32_t f = 0; f < remesh.num_faces(); ++f) F[f] = {remesh.f0[f], remesh.f1[f], remesh.f2[f]};
  std::vector<uint8_t> fixed(n, 0);
  for (const auto& loop : boundary_loops(remesh))
    for (int32_t v : loop) fixed[v] = 1;
  for (size_t v = 0; v < opt.pinned.size() && v < fixed.size(); ++v) fixed[v] = fixed[v] || opt.pinned[v];
  const Csr vf = make_csr(n, static_cast<int32_t>(F.size()), [&](int32_t f, auto&& put) {
    for (int32_t v : F[f]) put(v);
  });
  int64_t moves = 0;
  std::vector<int32_t> faces, near;
  // The mean smallest angle the pass may spend: at most budget_deg, never
  // below mean_floor_deg.
  double total = 0;
  for (const auto& t : F) total += min_angle(pos(remesh, t[0]), pos(remesh, t[1]), pos(remesh, t[2]));
  const double tris = static_cast<double>(F.size());
  double budget = std::max(0.0, std::min(opt.budget_deg * M_PI / 180, total / tris - opt.mean_floor_deg * M_PI / 180)) * tris;
  // Each input vertex's nearest remesh triangle, once over a grid, then
  // kept up to date around each move (refresh). A move can also bring one of
  // v's triangles nearer to an input vertex owned elsewhere: its distance is
  // then too large, so each pass queries again, over a new grid, those at
  // the candidates' distance, until the farthest is exact.
  std::vector<ClosestPoint> cp(ni);
  if (opt.passes > 0) {
    const TriangleGrid rg(remesh);
    tbb::parallel_for(0, ni, [&](int32_t i) { cp[i] = rg.closest(pos(input, i)); });
  }
  auto farthest = [&] {
    double far = 0;
    for (const ClosestPoint& c : cp) far = std::max(far, c.distance);
    return far;
  };
  for (int pass = 0; pass < opt.passes; ++pass) {
    double far = farthest();
    if (pass > 0) {
      const TriangleGrid rg(remesh);
      std::vector<uint8_t> fresh(ni, 0);
      for (bool again = true; again;) {
        std::vector<int32_t> stale;
        for (int32_t i = 0; i < ni; ++i)
          if (!fresh[i] && cp[i].distance >= opt.candidates * far) stale.push_back(i);
        tbb::parallel_for(size_t{0}, stale.size(), [&](size_t k) { cp[stale[k]] = rg.closest(pos(input, stale[k])); });
        for (int32_t i : stale) fresh[i] = 1;
        again = !stale.empty();
        far = farthest();
      }
    }
    const Csr owned = make_csr(n, ni, [&](int32_t i, auto&& put) {
      if (cp[i].face >= 0)
        for (int32_t v : F[cp[i].face]) put(v);
    });
    std::vector<int32_t> order;
    for (int32_t i = 0; i < ni; ++i)
      if (cp[i].face >= 0 && cp[i].distance >= opt.candidates * far && far > 0) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](int32_t a, int32_t b) {
      return cp[a].distance != cp[b].distance ? cp[a].distance > cp[b].distance : a < b;
    });
    const Pass P{input, grid, remesh, F, vf, owned, opt.keep_deg * M_PI / 180};
    std::vector<uint8_t> moved(n, 0);
    int64_t k = 0;
    for (int32_t i : order) {
      if (cp[i].distance < opt.candidates * far) continue;  // nearer since a move
      // The vertices of i's nearest triangle, nearest to i first.
      std::array<int32_t, 3> t = F[cp[i].face];
      std::sort(t.begin(), t.end(), [&](int32_t a, int32_t b) {
        return dot(sub(pos(remesh, a), pos(input, i)), sub(pos(remesh, a), pos(input, i))) <
               dot(sub(pos(remesh, b), pos(input, i)), sub(pos(remesh, b), pos(input, i)));
      });
      int32_t v = -1;
      for (int32_t w : t)
        if (!fixed[w] && !moved[w] && P.pull(w, i, faces, near, budget)) {
          v = w;
          break;
        }
      if (v < 0) continue;
      // v's ring waits for the next pass: its triangles' nearest input
      // vertices (`owned`) are out of date now.
      for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q)
        for (int32_t w : F[vf.item[q]]) moved[w] = 1;
      P.refresh(v, cp, faces);
      ++k;
    }
    moves += k;
    if (k == 0) break;
  }
  return moves;
}

}  // namespace locus
