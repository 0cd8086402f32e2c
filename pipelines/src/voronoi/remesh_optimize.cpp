// Edge flips and tangential smoothing of a remesh on its input
// (pipelines/include/locus/pipelines/voronoi/remesh_optimize.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_optimize.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/remesh_boundary.hpp"
#include "remesh_flips.hpp"
#include "remesh_vec3.hpp"

namespace locus {

namespace {

using namespace remesh_vec3;

// Per vertex: its incident triangles (CSR); flips change it, moves do not.
struct VertexFaces {
  std::vector<int64_t> off;
  std::vector<int32_t> f;
  VertexFaces(int32_t n, const std::vector<std::array<int32_t, 3>>& F) : off(static_cast<size_t>(n) + 1, 0) {
    for (const auto& t : F)
      for (int32_t v : t) ++off[v + 1];
    for (int32_t v = 0; v < n; ++v) off[v + 1] += off[v];
    f.resize(static_cast<size_t>(off[n]));
    std::vector<int64_t> fill(off.begin(), off.end() - 1);
    for (int32_t t = 0; t < static_cast<int32_t>(F.size()); ++t)
      for (int32_t v : F[t]) f[fill[v]++] = t;
  }
};

// The unit normal of v's ring (the sum of its triangles' vector areas); false when
// the ring has no area or its normals cancel.
bool ring_normal(const Mesh& m, const std::vector<std::array<int32_t, 3>>& F, const VertexFaces& vf, int32_t v,
                 V3& nv) {
  nv = {0, 0, 0};
  double area = 0;
  for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
    const auto& t = F[vf.f[q]];
    const V3 p0 = pos(m, t[0]), p1 = pos(m, t[1]), p2 = pos(m, t[2]);
    const V3 nn = tri_normal(p0, p1, p2);
    const double a = 0.5 * norm(nn);
    for (int k = 0; k < 3; ++k) nv[k] += nn[k];
    area += a;
  }
  const double ln = norm(nv);
  if (!(area > 0) || !(ln > 0)) return false;
  for (int k = 0; k < 3; ++k) nv[k] /= ln;
  return true;
}

// The smoothing target: the mean of the ring's vertices (each counted once per
// incident triangle).
V3 ring_mean(const Mesh& m, const std::vector<std::array<int32_t, 3>>& F, const VertexFaces& vf, int32_t v) {
  V3 u{0, 0, 0}, c;
  int cnt = 0;
  for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q)
    for (int32_t w : F[vf.f[q]])
      if (w != v) {
        u[0] += m.x[w];
        u[1] += m.y[w];
        u[2] += m.z[w];
        ++cnt;
      }
  for (int k = 0; k < 3; ++k) c[k] = u[k] / cnt;
  return c;
}

// Tips and ridges (an incident triangle turned more than 60 degrees from the
// vertex normal) keep their vertex: moving it would cut the feature off; unless
// one of its triangles has an angle below unpin_below (docs/cvt.md).
bool pinned_feature(const Mesh& m, const std::vector<std::array<int32_t, 3>>& F, const VertexFaces& vf, int32_t v,
                    const V3& nv, double unpin_below) {
  const double cos_pin = 0.5;
  double worst = M_PI;
  for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
    const auto& t = F[vf.f[q]];
    worst = std::min(worst, min_angle(pos(m, t[0]), pos(m, t[1]), pos(m, t[2])));
  }
  for (int64_t q = vf.off[v]; q < vf.off[v + 1] && worst >= unpin_below; ++q) {
    const auto& t = F[vf.f[q]];
    const V3 nn = tri_normal(pos(m, t[0]), pos(m, t[1]), pos(m, t[2]));
    if (dot(nn, nv) < cos_pin * norm(nn)) return true;
  }
  return false;
}

// v moved by d from p and projected onto the input: the full move, else half,
// else a quarter (a vertex squeezed between close neighbors can still spread
// out), accepted when the input's triangle there faces like the ring and no
// incident triangle turns over. False when every step is refused.
bool project_move(const Mesh& input, const TriangleGrid& grid, const Mesh& m,
                  const std::vector<std::array<int32_t, 3>>& F, const VertexFaces& vf, int32_t v, const V3& nv,
                  const V3& p, const V3& d, V3& out) {
  for (double step : {1.0, 0.5, 0.25}) {
    const V3 goal = {p[0] + step * d[0], p[1] + step * d[1], p[2] + step * d[2]};
    const ClosestPoint cp = grid.closest(goal);
    bool ok = cp.face >= 0;
    if (ok) {
      const auto fv = input.face(cp.face);
      const V3 ni = tri_normal(pos(input, fv[0]), pos(input, fv[1]), pos(input, fv[2]));
      ok = dot(ni, nv) > 0.5 * norm(ni);
    }
    for (int64_t q = vf.off[v]; ok && q < vf.off[v + 1]; ++q) {  // no incident triangle turns over
      std::array<V3, 3> a, b;
      for (int k = 0; k < 3; ++k) {
        a[k] = pos(m, F[vf.f[q]][k]);
        b[k] = F[vf.f[q]][k] == v ? cp.point : a[k];
      }
      const V3 n0 = tri_normal(a[0], a[1], a[2]), n1 = tri_normal(b[0], b[1], b[2]);
      // A degenerate triangle (no normal beyond rounding noise) may open up in
      // the vertex normal's direction.
      const double scale = std::max({dot(sub(a[1], a[0]), sub(a[1], a[0])), dot(sub(a[2], a[0]), sub(a[2], a[0])),
                                     dot(sub(a[2], a[1]), sub(a[2], a[1]))});
      ok = norm(n0) > 1e-12 * scale ? dot(n0, n1) > 0.5 * norm(n0) * norm(n1) : dot(n1, nv) > 0;
    }
    if (ok) {
      out = cp.point;
      return true;
    }
  }
  return false;
}

// One Jacobi sweep of tangential smoothing with projection onto the input: each
// free vertex moves towards its ring's mean, in its tangent plane.
void smooth_pass(const Mesh& input, const TriangleGrid& grid, Mesh& m, const std::vector<std::array<int32_t, 3>>& F,
                 const std::vector<uint8_t>& fixed, double unpin_below, RemeshOptimizeStats& st) {
  const int32_t n = m.num_vertices();
  const VertexFaces vf(n, F);
  std::vector<V3> next(n);
  std::vector<uint8_t> state(n, 0);  // 0 unchanged, 1 moved, 2 refused, 3 pinned
  tbb::parallel_for(0, n, [&](int32_t v) {
    next[v] = pos(m, v);
    V3 nv;
    if (fixed[v] || vf.off[v] == vf.off[v + 1] || !ring_normal(m, F, vf, v, nv)) return;
    V3 d = sub(ring_mean(m, F, vf, v), next[v]);
    const double dn = dot(d, nv);
    for (int k = 0; k < 3; ++k) d[k] -= dn * nv[k];
    if (pinned_feature(m, F, vf, v, nv, unpin_below)) {
      state[v] = 3;
      return;
    }
    state[v] = project_move(input, grid, m, F, vf, v, nv, next[v], d, next[v]) ? 1 : 2;
  });
  for (int32_t v = 0; v < n; ++v) {
    m.x[v] = next[v][0];
    m.y[v] = next[v][1];
    m.z[v] = next[v][2];
    st.moves += state[v] == 1;
    st.refused += state[v] == 2;
  }
}

// The smallest angle of v's triangles with v at p; -1 when a triangle would
// turn more than 60 degrees from its current normal (or over). A degenerate
// triangle (no normal beyond rounding noise) may open up on the side of the
// vertex normal nv: otherwise a vertex of a collinear triple could never move.
// With `sum`, also the sum of the triangles' smallest angles.
double ring_min_angle(const Mesh& m, const std::vector<std::array<int32_t, 3>>& F, const VertexFaces& vf, int32_t v,
                      const V3& nv, const V3& p, double* sum = nullptr) {
  double worst = M_PI;
  if (sum) *sum = 0;
  for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
    const auto& t = F[vf.f[q]];
    std::array<V3, 3> a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = pos(m, t[k]);
      b[k] = t[k] == v ? p : a[k];
    }
    const V3 n0 = tri_normal(a[0], a[1], a[2]), n1 = tri_normal(b[0], b[1], b[2]);
    const double scale = std::max({dot(sub(a[1], a[0]), sub(a[1], a[0])), dot(sub(a[2], a[0]), sub(a[2], a[0])),
                                   dot(sub(a[2], a[1]), sub(a[2], a[1]))});
    const bool flat = !(norm(n0) > 1e-3 * scale);  // a sliver below ~0.06 degrees: its normal is noise
    if (flat ? !(dot(n1, nv) > 0) : dot(n0, n1) <= 0.5 * norm(n0) * norm(n1)) return -1;
    const double mt = min_angle(b[0], b[1], b[2]);
    worst = std::min(worst, mt);
    if (sum) *sum += mt;
  }
  return worst;
}

// Targeted repair of the triangles the smoothing leaves below `below` radians
// (thin triangles at pinned tips): each free vertex of one climbs, in its
// tangent plane and projected onto the input, to the largest smallest angle of
// its triangles (pattern search, 8 directions, steps of 1/4 to 1/32 of its mean
// edge); moving a tip's neighbors opens the tip's angle and keeps the Hausdorff
// distance. Sequential in vertex order (deterministic). With `by_sum`, every
// free vertex climbs, lexicographically: its smallest angle up to `below`, then
// the sum of its triangles' smallest angles; from 1/8 of an edge; tips and
// ridges within tip_reach of `home` (else the sum cuts them a little every
// sweep); no ring edge longer than edge_growth times the longest at the start
// (0: no bound) unless the ring is flat (all within 20 degrees of the vertex
// normal: blade 49.4 -> 50.4 degrees) or its chord error does not grow
// (docs/cvt.md). Returns the number of moves.
constexpr double kFlatCos = 0.93969262078590838;  // cos 20 degrees

// The longest edge from v, at p, to its ring.
double ring_max_edge(const Mesh& m, const std::vector<std::array<int32_t, 3>>& F, const VertexFaces& vf, int32_t v,
                     const V3& p) {
  double l = 0;
  for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q)
    for (int32_t w : F[vf.f[q]])
      if (w != v) l = std::max(l, norm(sub(pos(m, w), p)));
  return l;
}

// The chord error of v's ring with v at p: the largest distance from the
// midpoint of an edge from v, or from a triangle's centroid, to the input.
double ring_chord_error(const TriangleGrid& grid, const Mesh& m, const std::vector<std::array<int32_t, 3>>& F,
                        const VertexFaces& vf, int32_t v, const V3& p) {
  double e = 0;
  for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
    const auto& t = F[vf.f[q]];
    V3 c = {0, 0, 0};
    for (int32_t w : t) {
      const V3 pw = w == v ? p : pos(m, w);
      for (int k = 0; k < 3; ++k) c[k] += pw[k] / 3;
      if (w == v) continue;
      const V3 mid = {0.5 * (p[0] + pw[0]), 0.5 * (p[1] + pw[1]), 0.5 * (p[2] + pw[2])};
      const ClosestPoint cp = grid.closest(mid);
      if (cp.face >= 0) e = std::max(e, norm(sub(cp.point, mid)));
    }
    const ClosestPoint cp = grid.closest(c);
    if (cp.face >= 0) e = std::max(e, norm(sub(cp.point, c)));
  }
  return e;
}

// One vertex's climb (see angle_pass); true with `out` when it found a better place.
bool climb_vertex(const Mesh& input, const TriangleGrid& grid, const Mesh& m,
                  const std::vector<std::array<int32_t, 3>>& F, const VertexFaces& vf, int32_t v, double below,
                  double tip_reach, bool by_sum, double edge_growth, const std::vector<V3>& home, V3& out) {
  V3 nv{0, 0, 0};
  double len = 0;
  int cnt = 0;
  for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q) {
    const auto& t = F[vf.f[q]];
    const V3 nn = tri_normal(pos(m, t[0]), pos(m, t[1]), pos(m, t[2]));
    for (int k = 0; k < 3; ++k) nv[k] += nn[k];
    for (int32_t w : t)
      if (w != v) len += norm(sub(pos(m, w), pos(m, v))), ++cnt;
  }
  const double ln = norm(nv);
  if (!(ln > 0) || cnt == 0) return false;
  for (int k = 0; k < 3; ++k) nv[k] /= ln;
  len /= cnt;
  bool tip = false, flat = true;
  for (int64_t q = vf.off[v]; q < vf.off[v + 1] && !tip; ++q) {
    const auto& t = F[vf.f[q]];
    const V3 nn = tri_normal(pos(m, t[0]), pos(m, t[1]), pos(m, t[2]));
    tip = dot(nn, nv) < 0.5 * norm(nn);
    flat = flat && dot(nn, nv) >= kFlatCos * norm(nn);
  }
  if (tip && !(tip_reach > 0)) return false;
  const V3 origin = by_sum ? home[v] : pos(m, v);
  const double reach2 = tip ? tip_reach * tip_reach * len * len : HUGE_VAL;
  // Tangent basis.
  const V3 axis = std::abs(nv[0]) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
  V3 e1 = cross(nv, axis);
  const double l1 = norm(e1);
  for (double& x : e1) x /= l1;
  const V3 e2 = cross(nv, e1);
  V3 best = pos(m, v);
  double cur_sum = 0;
  double cur = ring_min_angle(m, F, vf, v, nv, best, &cur_sum);
  const double max_edge = by_sum && edge_growth > 0 && !flat ? edge_growth * ring_max_edge(m, F, vf, v, best) : HUGE_VAL;
  double max_chord = -1;  // the starting ring's chord error, computed when first needed
  const V3 start = best;
  auto chord_ok = [&](const V3& p) {
    if (max_chord < 0) max_chord = ring_chord_error(grid, m, F, vf, v, start);
    return ring_chord_error(grid, m, F, vf, v, p) <= max_chord;
  };
  auto better = [&](double q, double q_sum) {
    if (q < 0) return false;
    if (!by_sum) return q > cur + 1e-9;
    const double a = std::min(q, below), b = std::min(cur, below);
    if (a != b) return a > b + 1e-9;
    return q_sum > cur_sum + 1e-9;
  };
  bool improved = false;
  for (double step = (by_sum ? 0.125 : 0.25) * len; step > len / 40; step *= 0.5) {
    for (int climb = 0; climb < 6; ++climb) {
      bool found = false;
      for (int dir = 0; dir < 8; ++dir) {
        const double th = dir * M_PI / 4, c = std::cos(th) * step, s = std::sin(th) * step;
        const V3 goal = {best[0] + c * e1[0] + s * e2[0], best[1] + c * e1[1] + s * e2[1],
                         best[2] + c * e1[2] + s * e2[2]};
        const ClosestPoint cp = grid.closest(goal);
        if (cp.face < 0) continue;
        const V3 moved = sub(cp.point, origin);
        if (dot(moved, moved) > reach2) continue;
        const auto fv = input.face(cp.face);
        const V3 ni = tri_normal(pos(input, fv[0]), pos(input, fv[1]), pos(input, fv[2]));
        if (dot(ni, nv) <= 0.5 * norm(ni)) continue;
        double q_sum = 0;
        const double q = ring_min_angle(m, F, vf, v, nv, cp.point, &q_sum);
        if (better(q, q_sum) && !(max_edge < HUGE_VAL && ring_max_edge(m, F, vf, v, cp.point) > max_edge &&
                                  !chord_ok(cp.point))) {
          cur = q;
          cur_sum = q_sum;
          improved = found = true;
          best = cp.point;
        }
      }
      if (!found) break;
    }
  }
  out = best;
  return improved;
}

// Greedy colors of the vertices in index order (no two vertices of a triangle
// share one): the vertices of one color can climb at once, each reading only
// its ring, so the sum's sweeps run in parallel with a result independent of
// the threads.
std::vector<std::vector<int32_t>> color_classes(int32_t n, const std::vector<std::array<int32_t, 3>>& F,
                                                const VertexFaces& vf, const std::vector<int32_t>& verts) {
  std::vector<int32_t> color(n, -1);
  std::vector<std::vector<int32_t>> classes;
  std::vector<uint8_t> used;
  for (int32_t v : verts) {
    used.assign(classes.size() + 1, 0);
    for (int64_t q = vf.off[v]; q < vf.off[v + 1]; ++q)
      for (int32_t w : F[vf.f[q]])
        if (w != v && color[w] >= 0) used[color[w]] = 1;
    int32_t c = 0;
    while (used[c]) ++c;
    color[v] = c;
    if (c == static_cast<int32_t>(classes.size())) classes.emplace_back();
    classes[c].push_back(v);
  }
  return classes;
}

// One sweep of climbs: the repair's vertices or, by_sum, every free vertex.
int64_t angle_pass(const Mesh& input, const TriangleGrid& grid, Mesh& m, const std::vector<std::array<int32_t, 3>>& F,
                   const std::vector<uint8_t>& fixed, double below, double tip_reach, bool by_sum,
                   double edge_growth, const std::vector<V3>& home, RemeshOptimizeStats& st) {
  const VertexFaces vf(m.num_vertices(), F);
  std::vector<int32_t> bad;
  for (const auto& t : F)
    if (by_sum || min_angle(pos(m, t[0]), pos(m, t[1]), pos(m, t[2])) < below)
      bad.insert(bad.end(), t.begin(), t.end());
  std::sort(bad.begin(), bad.end());
  bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
  int64_t moves = 0;
  if (!by_sum) {  // a few vertices: sequential, in vertex order
    for (int32_t v : bad) {
      V3 p;
      if (fixed[v] || vf.off[v] == vf.off[v + 1] || !climb_vertex(input, grid, m, F, vf, v, below, tip_reach, false, 0, home, p))
        continue;
      m.x[v] = p[0];
      m.y[v] = p[1];
      m.z[v] = p[2];
      ++moves;
    }
  } else {
    bad.erase(std::remove_if(bad.begin(), bad.end(), [&](int32_t v) { return fixed[v] || vf.off[v] == vf.off[v + 1]; }),
              bad.end());
    for (const std::vector<int32_t>& cls : color_classes(m.num_vertices(), F, vf, bad)) {
      std::vector<V3> to(cls.size());
      std::vector<uint8_t> moved(cls.size(), 0);
      tbb::parallel_for(size_t{0}, cls.size(), [&](size_t i) {
        moved[i] = climb_vertex(input, grid, m, F, vf, cls[i], below, tip_reach, true, edge_growth, home, to[i]);
      });
      for (size_t i = 0; i < cls.size(); ++i)
        if (moved[i]) {
          m.x[cls[i]] = to[i][0];
          m.y[cls[i]] = to[i][1];
          m.z[cls[i]] = to[i][2];
          ++moves;
        }
    }
  }
  st.angle_moves += moves;
  return moves;
}

}  // namespace

RemeshOptimizeStats optimize_remesh(const Mesh& input, const TriangleGrid& grid, Mesh& remesh,
                                    const RemeshOptimizeOptions& opt) {
  if (!remesh.is_triangle_mesh()) fail(ErrorCode::BadUsage, "optimize remesh: a triangle mesh expected");
  if (opt.rounds < 0) fail(ErrorCode::BadUsage, "optimize remesh: rounds must be >= 0");
  RemeshOptimizeStats st;
  const int32_t n = remesh.num_vertices();
  std::vector<uint8_t> fixed(n, 0);
  for (const auto& loop : boundary_loops(remesh))
    for (int32_t v : loop) fixed[v] = 1;
  std::vector<std::array<int32_t, 3>> F(remesh.num_faces());
  for (int32_t f = 0; f < remesh.num_faces(); ++f) F[f] = {remesh.f0[f], remesh.f1[f], remesh.f2[f]};
  BoundaryCurves curves(input, remesh);  // the boundary vertices move along the input's boundary only
  for (const FeatureCurve& c : opt.slides) curves.add_curve(c.p, c.closed, c.site, c.s);
  std::vector<int32_t> valence(n, 0), target(n, 6);
  for (const auto& t : F)
    for (int32_t v : t) ++valence[v];
  for (int32_t v = 0; v < n; ++v)
    if (fixed[v]) target[v] = 4;
  if (!opt.pinned.empty() && opt.pinned.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "optimize remesh: pinned must have one entry per vertex");
  for (int32_t v = 0; v < static_cast<int32_t>(opt.pinned.size()); ++v) fixed[v] = fixed[v] || opt.pinned[v];
  FeatureEdges features(opt.slides, opt.pinned);
  const FlipContext fc{input, grid, features, fixed, curves};
  // Delaunay flips first (the discrete cells' connectivity) and last; valence
  // flips in the rounds between (both at once undo each other: docs/cvt.md).
  for (int r = 0; r <= opt.rounds; ++r) {
    for (int by_valence = 1; by_valence >= 0; --by_valence) {
      if (by_valence != (r > 0 && r < opt.rounds)) continue;
      for (int pass = 0; pass < 8; ++pass) {
        const int64_t k = flip_pass(fc, remesh, F, valence, target, by_valence);
        st.flips += k;
        if (k == 0) break;
      }
    }
    if (r < opt.rounds) {
      smooth_pass(input, grid, remesh, F, fixed, opt.unpin_below_deg * M_PI / 180, st);
      st.boundary_moves += curves.sweep(remesh, F, false);
    }
  }
  // The angle repair until a sweep changes nothing, the climbs of the sum,
  // then the repair again (the sum's climbs may leave a ring at `below`).
  const double below = opt.angle_below_deg * M_PI / 180;
  const double hard_below = opt.hard_below_deg * M_PI / 180;
  std::vector<V3> home(n);
  for (int32_t v = 0; v < n; ++v) home[v] = pos(remesh, v);
  auto angle_sweep = [&](bool by_sum, double pass_below, double reach) {
    int64_t changed = angle_pass(input, grid, remesh, F, fixed, pass_below, reach, by_sum, opt.sum_edge_growth, home, st);
    const int64_t b = curves.sweep(remesh, F, true);
    st.boundary_moves += b;
    changed += b;
    for (int pass = 0; pass < 8; ++pass) {
      const int64_t k = flip_pass(fc, remesh, F, valence, target, false);
      st.flips += k;
      changed += k;
      if (k == 0) break;
    }
    return changed;
  };
  for (int sweep = 0; sweep < opt.angle_sweeps && angle_sweep(false, below, opt.tip_reach) > 0; ++sweep) {
  }
  if (opt.sum_sweeps > 0) {
    for (int sweep = 0; sweep < opt.sum_sweeps; ++sweep) angle_sweep(true, below, opt.tip_reach);
    for (int sweep = 0; sweep < opt.angle_sweeps && angle_sweep(false, below, opt.tip_reach) > 0; ++sweep) {
    }
  }
  if (opt.angle_sweeps > 0 && hard_below > 0)
    for (int sweep = 0; sweep < opt.hard_sweeps && angle_sweep(false, hard_below, opt.hard_tip_reach) > 0; ++sweep) {
    }
  for (int32_t f = 0; f < remesh.num_faces(); ++f) {
    remesh.f0[f] = F[f][0];
    remesh.f1[f] = F[f][1];
    remesh.f2[f] = F[f][2];
    for (int k = 0; k < 3; ++k) remesh.face_vertices[3 * static_cast<size_t>(f) + k] = F[f][k];
  }
  return st;
}

}  // namespace locus
