// Remesh boundary vertices sliding along the input's boundary curves
// (pipelines/include/locus/pipelines/voronoi/remesh_boundary.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_boundary.hpp"

#include <algorithm>
#include <cmath>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "remesh_vec3.hpp"

namespace locus {

namespace {

using namespace remesh_vec3;
double pos_mod(double x, double len) {
  const double r = std::fmod(x, len);
  return r < 0 ? r + len : r;
}

// The smallest angle of v's triangles with v at p; -1 when one would turn more
// than 60 degrees from its current normal (or over).
double ring_min_angle(const Mesh& m, const std::vector<std::array<int32_t, 3>>& F, const std::vector<int32_t>& faces,
                      int32_t v, const V3& p) {
  double worst = M_PI;
  for (int32_t f : faces) {
    std::array<V3, 3> a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = pos(m, F[f][k]);
      b[k] = F[f][k] == v ? p : a[k];
    }
    const V3 n0 = cross(sub(a[1], a[0]), sub(a[2], a[0])), n1 = cross(sub(b[1], b[0]), sub(b[2], b[0]));
    if (norm(n0) > 0 && dot(n0, n1) <= 0.5 * norm(n0) * norm(n1)) return -1;
    worst = std::min({worst, angle_at(b[0], b[1], b[2]), angle_at(b[1], b[2], b[0]), angle_at(b[2], b[0], b[1])});
  }
  return worst;
}

}  // namespace

std::array<double, 3> BoundaryCurves::at(const Curve& c, double s) const {
  const double len = c.s.back();
  s = pos_mod(s, len);
  const size_t k = c.p.size();
  size_t i = static_cast<size_t>(std::upper_bound(c.s.begin(), c.s.end(), s) - c.s.begin());
  i = std::min(k - 1, i > 0 ? i - 1 : 0);
  const double seg = c.s[i + 1] - c.s[i], w = seg > 0 ? (s - c.s[i]) / seg : 0.0;
  const V3& a = c.p[i];
  const V3& b = c.p[(i + 1) % k];
  return {a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), a[2] + w * (b[2] - a[2])};
}

BoundaryCurves::BoundaryCurves(const Mesh& input, const Mesh& remesh) {
  // A closed remesh has no vertex to slide: the input's loops (an edge
  // incidence of the whole input, ~0.15 s at 416k vertices) are not read.
  const std::vector<std::vector<int32_t>> remesh_loops = boundary_loops(remesh);
  if (remesh_loops.empty()) return;
  for (const std::vector<int32_t>& loop : boundary_loops(input)) {
    Curve c;
    const size_t k = loop.size();
    if (k < 3) continue;
    c.s.push_back(0);
    for (size_t i = 0; i < k; ++i) {
      c.p.push_back(pos(input, loop[i]));
      const V3 a = pos(input, loop[(i + k - 1) % k]), v = pos(input, loop[i]), b = pos(input, loop[(i + 1) % k]);
      const V3 u = sub(v, a), w = sub(b, v);
      if (norm(u) > 0 && norm(w) > 0 && dot(u, w) < std::sqrt(0.5) * norm(u) * norm(w)) c.corners.push_back(c.s.back());
      c.s.push_back(c.s.back() + norm(w));
    }
    if (c.s.back() > 0) curves_.push_back(std::move(c));
  }
  for (const std::vector<int32_t>& loop : remesh_loops) {
    if (loop.size() < 3) continue;
    Run r;
    std::vector<double> s;
    for (int32_t v : loop) {  // nearest point of every input boundary segment
      const V3 p = pos(remesh, v);
      double best = INFINITY, bs = 0;
      int32_t bc = -1;
      for (size_t ci = 0; ci < curves_.size(); ++ci) {
        const Curve& c = curves_[ci];
        for (size_t i = 0; i < c.p.size(); ++i) {
          const V3 a = c.p[i], d = sub(c.p[(i + 1) % c.p.size()], a);
          const double l2 = dot(d, d), t = l2 > 0 ? std::clamp(dot(sub(p, a), d) / l2, 0.0, 1.0) : 0.0;
          const V3 q = {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
          const double dd = dot(sub(p, q), sub(p, q));
          if (dd < best) best = dd, bs = c.s[i] + t * (c.s[i + 1] - c.s[i]), bc = static_cast<int32_t>(ci);
        }
      }
      if (r.curve >= 0 && bc != r.curve) r.curve = -2;
      if (r.curve == -1) r.curve = bc;
      s.push_back(bs);
    }
    if (r.curve < 0) continue;
    const Curve& c = curves_[r.curve];
    const double len = c.s.back();
    double turn = 0;  // wrapped steps around the loop: +-len when the run goes round once
    for (size_t i = 0; i < s.size(); ++i) turn += pos_mod(s[(i + 1) % s.size()] - s[i] + len / 2, len) - len / 2;
    if (std::abs(std::abs(turn) - len) > 1e-6 * len) continue;
    r.dir = turn > 0 ? 1 : -1;
    r.v = loop;
    r.u.push_back(r.dir * s[0]);
    for (size_t i = 1; i < s.size(); ++i) r.u.push_back(r.u.back() + pos_mod(r.dir * (s[i] - s[i - 1]), len));
    if (r.u.back() >= r.u[0] + len) continue;
    for (double u : r.u) {
      bool pin = false;
      for (double cs : c.corners) pin = pin || std::abs(pos_mod(r.dir * cs - u + len / 2, len) - len / 2) < 1e-7 * len;
      r.pinned.push_back(pin);
    }
    runs_.push_back(std::move(r));
  }
}

void BoundaryCurves::add_curve(const std::vector<std::array<double, 3>>& p, bool closed, std::vector<int32_t> v,
                               std::vector<double> u) {
  if (p.size() < 2 || v.size() < (closed ? 3u : 2u) || v.size() != u.size()) return;
  Curve c;
  c.p = p;
  c.s.push_back(0);
  for (size_t i = 0; i < p.size(); ++i) c.s.push_back(c.s.back() + norm(sub(p[(i + 1) % p.size()], p[i])));
  if (!closed) c.s.back() = c.s[p.size() - 1] + 1;  // no way back: the open end (never reached) wraps
  Run r;
  r.curve = static_cast<int32_t>(curves_.size());
  r.v = std::move(v);
  r.u = std::move(u);
  r.pinned.assign(r.v.size(), 0);
  r.closed = closed;
  if (!closed) r.pinned.front() = r.pinned.back() = 1;
  curves_.push_back(std::move(c));
  runs_.push_back(std::move(r));
}

bool BoundaryCurves::adopt(Mesh& remesh, int32_t a, int32_t b, int32_t c) {
  for (Run& r : runs_) {
    const size_t k = r.v.size();
    for (size_t i = 0; i < k; ++i) {
      const size_t j = (i + 1) % k;
      if (j == 0 && !r.closed) break;  // an open run's ends are no neighbors
      if (!((r.v[i] == a && r.v[j] == b) || (r.v[i] == b && r.v[j] == a))) continue;
      const Curve& cv = curves_[r.curve];
      const double ui = r.u[i], uj = j == 0 ? r.u[0] + cv.s.back() : r.u[j];
      const V3 p = pos(remesh, c);
      const double di = norm(sub(p, pos(remesh, r.v[i]))), dj = norm(sub(p, pos(remesh, r.v[j])));
      const double uc = di + dj > 0 ? ui + (uj - ui) * di / (di + dj) : 0.5 * (ui + uj);
      const V3 q = at(cv, r.dir * uc);
      remesh.x[c] = q[0], remesh.y[c] = q[1], remesh.z[c] = q[2];
      const auto at_i = static_cast<std::ptrdiff_t>(i + 1);
      r.v.insert(r.v.begin() + at_i, c);
      r.u.insert(r.u.begin() + at_i, uc);
      r.pinned.insert(r.pinned.begin() + at_i, 0);
      return true;
    }
  }
  return false;
}

int64_t BoundaryCurves::movable() const {
  int64_t k = 0;
  for (const Run& r : runs_)
    for (uint8_t p : r.pinned) k += !p;
  return k;
}

int64_t BoundaryCurves::sweep(Mesh& remesh, const std::vector<std::array<int32_t, 3>>& F, bool by_angle) {
  std::vector<std::vector<int32_t>> faces(remesh.num_vertices());
  for (const Run& r : runs_)
    for (int32_t v : r.v)
      if (faces[v].empty()) faces[v].push_back(-1);  // marks (once) the vertices whose triangles are needed
  for (int32_t f = 0; f < static_cast<int32_t>(F.size()); ++f)
    for (int32_t v : F[f])
      if (!faces[v].empty()) faces[v].push_back(f);
  for (auto& l : faces)
    if (!l.empty()) l.erase(l.begin());
  int64_t moves = 0;
  const double kSmoothFloor = 20 * M_PI / 180;
  for (Run& r : runs_) {
    const Curve& c = curves_[r.curve];
    const double len = c.s.back();
    const size_t k = r.v.size();
    for (size_t i = 0; i < k; ++i) {
      if (r.pinned[i]) continue;
      const int32_t v = r.v[i];
      const double u = r.u[i];
      const double prev = i > 0 ? r.u[i - 1] : r.u[k - 1] - len, next = i + 1 < k ? r.u[i + 1] : r.u[0] + len;
      double lo = prev, hi = next;  // and no corner crossed
      for (double cs : c.corners) {
        lo = std::max(lo, u - pos_mod(u - r.dir * cs, len));
        hi = std::min(hi, u + pos_mod(r.dir * cs - u, len));
      }
      const double margin = 0.05 * (next - prev);
      lo = std::max(lo, prev + margin);
      hi = std::min(hi, next - margin);
      if (!(lo < hi)) continue;
      const double start = ring_min_angle(remesh, F, faces[v], v, pos(remesh, v));
      double best_u = u, best = start;
      if (by_angle) {
        for (double step = (next - prev) / 8; step > (next - prev) / 200; step *= 0.5)
          for (bool found = true; found;) {
            found = false;
            for (double cand : {best_u - step, best_u + step}) {
              if (cand < lo || cand > hi) continue;
              const double q = ring_min_angle(remesh, F, faces[v], v, at(c, r.dir * cand));
              if (q > best + 1e-9) best = q, best_u = cand, found = true;
            }
          }
      } else {
        const double cand = std::clamp(0.5 * (prev + next), lo, hi);
        const double q = ring_min_angle(remesh, F, faces[v], v, at(c, r.dir * cand));
        if (q >= 0 && q >= std::min(start, kSmoothFloor)) best_u = cand;
      }
      if (best_u == u) continue;
      const V3 p = at(c, r.dir * best_u);
      remesh.x[v] = p[0];
      remesh.y[v] = p[1];
      remesh.z[v] = p[2];
      r.u[i] = best_u;
      ++moves;
    }
  }
  return moves;
}

}  // namespace locus
