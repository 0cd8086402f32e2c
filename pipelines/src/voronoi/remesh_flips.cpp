// Edge flips of a remesh on its input
// (pipelines/src/voronoi/remesh_flips.hpp; thesis §3.7.1).
#include "remesh_flips.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "remesh_vec3.hpp"

namespace locus {

namespace {

using namespace remesh_vec3;

constexpr double kFlatAngle = 170 * M_PI / 180;

uint64_t key(int32_t a, int32_t b) {
  return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
}

using TriangleCorners = std::array<V3, 3>;

// The input's normal at the point of the input nearest a triangle's centroid.
bool input_normal_at(const Mesh& input, const TriangleGrid& grid, const TriangleCorners& t, V3& n) {
  const ClosestPoint cp = grid.closest(
      {(t[0][0] + t[1][0] + t[2][0]) / 3, (t[0][1] + t[1][1] + t[2][1]) / 3, (t[0][2] + t[1][2] + t[2][2]) / 3});
  if (cp.face < 0) return false;
  const auto fv = input.face(cp.face);
  n = tri_normal(pos(input, fv[0]), pos(input, fv[1]), pos(input, fv[2]));
  return norm(n) > 0;
}

// For a pair `before` whose normals are more than 120 degrees apart (the
// caller's test: a fold, not a crease): true when it is folded against the
// input (one of its triangles more than 90 degrees off the input's normal)
// and the flipped pair `after` faces like the input (both within 60
// degrees): the flip unfolds it (polygon_mesh's boundary: a 4-degree ear
// folded 177 degrees onto its neighbor, which the 30-degree crease rule
// below kept; docs/cvt.md).
bool unfolds(const Mesh& input, const TriangleGrid& grid, const std::array<TriangleCorners, 2>& before,
             const std::array<TriangleCorners, 2>& after) {
  V3 ni;
  for (const TriangleCorners& t : after) {
    const V3 n = tri_normal(t[0], t[1], t[2]);
    if (!input_normal_at(input, grid, t, ni) || dot(n, ni) <= 0.5 * norm(n) * norm(ni)) return false;
  }
  for (const TriangleCorners& t : before)
    if (input_normal_at(input, grid, t, ni) && dot(tri_normal(t[0], t[1], t[2]), ni) < 0) return true;
  return false;
}

// The flip of the pair (a, b, c), (b, a, d) to (c, a, d), (d, b, c) keeps the
// surface: the new pair within 30 degrees of itself; an old pair across a
// crease (more than 30 degrees) only when it is a fold the flip opens; a
// degenerate old triangle oriented by its neighbor. With feature curves, a
// triangle whose angle opposite the edge is above 170 degrees counts as
// degenerate: its normal is noise (a vertex projected onto a crease between
// the edge's ends, where no move takes it off; hand 2.6 -> 18.4 degrees).
// Without them the moves resolve it, and the rule changed 15 sample meshes
// either way (docs/cvt.md).
// at_c, at_d: the old pair's angles opposite the edge.
bool keeps_surface(const FlipContext& fc, const V3& pa, const V3& pb, const V3& pc, const V3& pd, double at_c,
                   double at_d) {
  const double cos30 = std::cos(M_PI / 6);
  const V3 na = tri_normal(pa, pb, pc), nb = tri_normal(pb, pa, pd);
  const V3 n1 = tri_normal(pc, pa, pd), n2 = tri_normal(pd, pb, pc);
  // Degenerate (collinear) triangles have only a rounding-noise normal: zero it.
  const double scale = std::max({dot(sub(pa, pb), sub(pa, pb)), dot(sub(pc, pa), sub(pc, pa)), dot(sub(pd, pa), sub(pd, pa))});
  auto tiny = [&](double l) { return l <= 1e-12 * scale ? 0.0 : l; };
  const bool curves = fc.features.by_curves();
  const double la = curves && at_c > kFlatAngle ? 0.0 : tiny(norm(na));
  const double lb = curves && at_d > kFlatAngle ? 0.0 : tiny(norm(nb));
  const double l1 = tiny(norm(n1)), l2 = tiny(norm(n2));
  if (!(l1 > 0 && l2 > 0) || !(la > 0 || lb > 0)) return false;
  if (dot(n1, n2) < cos30 * l1 * l2) return false;
  if (la > 0 && lb > 0 && dot(na, nb) < cos30 * la * lb) {
    // A crease stays, unless the pair is a fold (more than 120 degrees) the flip opens.
    if (dot(na, nb) > -0.5 * la * lb ||
        !unfolds(fc.input, fc.grid, {{{pa, pb, pc}, {pb, pa, pd}}}, {{{pc, pa, pd}, {pd, pb, pc}}}))
      return false;
  } else {
    // A degenerate triangle (collinear sites, e.g. added on a straight input
    // edge) has no normal: its neighbor's orients the flip that removes it.
    const V3 navg = {(la > 0 ? na[0] / la : 0) + (lb > 0 ? nb[0] / lb : 0),
                     (la > 0 ? na[1] / la : 0) + (lb > 0 ? nb[1] / lb : 0),
                     (la > 0 ? na[2] / la : 0) + (lb > 0 ? nb[2] / lb : 0)};
    if (dot(n1, navg) <= 0 || dot(n2, navg) <= 0) return false;
  }
  return true;
}

}  // namespace

FeatureEdges::FeatureEdges(const std::vector<FeatureCurve>& slides, const std::vector<uint8_t>& pinned)
    : edges_(feature_curve_edges(slides)), pinned_(pinned) {}

bool FeatureEdges::kept(int32_t u, int32_t w) const {
  if (edges_.empty()) return !pinned_.empty() && pinned_[u] && pinned_[w];
  return std::binary_search(edges_.begin(), edges_.end(), std::pair{std::min(u, w), std::max(u, w)});
}

void FeatureEdges::split(int32_t a, int32_t b, int32_t c) {
  auto edge = [](int32_t u, int32_t w) { return std::pair{std::min(u, w), std::max(u, w)}; };
  const auto it = std::lower_bound(edges_.begin(), edges_.end(), edge(a, b));
  if (it != edges_.end() && *it == edge(a, b)) edges_.erase(it);
  for (const auto e : {edge(a, c), edge(c, b)}) edges_.insert(std::lower_bound(edges_.begin(), edges_.end(), e), e);
}

int64_t flip_pass(const FlipContext& fc, Mesh& m, std::vector<std::array<int32_t, 3>>& F,
                  std::vector<int32_t>& valence, const std::vector<int32_t>& target, bool by_valence) {
  std::unordered_map<uint64_t, std::array<int32_t, 2>> ef;
  ef.reserve(F.size() * 2);
  for (int32_t f = 0; f < static_cast<int32_t>(F.size()); ++f)
    for (int k = 0; k < 3; ++k) {
      auto [it, fresh] = ef.try_emplace(key(F[f][k], F[f][(k + 1) % 3]), std::array<int32_t, 2>{f, -1});
      if (!fresh) it->second[1] = f;
    }
  std::vector<uint64_t> edges;
  edges.reserve(ef.size());
  for (const auto& [k, v] : ef)
    if (v[1] >= 0) edges.push_back(k);
  std::sort(edges.begin(), edges.end());
  int64_t flips = 0;
  for (uint64_t e : edges) {
    const auto it = ef.find(e);
    if (it == ef.end() || it->second[1] < 0) continue;
    const int32_t fa = it->second[0], fb = it->second[1];
    const int32_t u = static_cast<int32_t>(e >> 32), w = static_cast<int32_t>(e & 0xffffffffu);
    const bool feature = fc.features.kept(u, w);
    if (feature && !fc.features.by_curves()) continue;  // a pinned pair stays
    // fa = (a, b, c) with the edge running a -> b in fa; fb = (b, a, d).
    int ka = 0;
    while (!((F[fa][ka] == u && F[fa][(ka + 1) % 3] == w) || (F[fa][ka] == w && F[fa][(ka + 1) % 3] == u))) ++ka;
    const int32_t a = F[fa][ka], b = F[fa][(ka + 1) % 3], c = F[fa][(ka + 2) % 3];
    int32_t d = -1;
    for (int k = 0; k < 3; ++k)
      if (F[fb][k] != a && F[fb][k] != b) d = F[fb][k];
    if (d < 0 || c == d || ef.count(key(c, d))) continue;
    const V3 pa = pos(m, a), pb = pos(m, b), pc = pos(m, c), pd = pos(m, d);
    const double at_c = angle_at(pc, pa, pb), at_d = angle_at(pd, pa, pb);
    int32_t on = -1;  // a free vertex on the feature edge: it joins the curve
    if (feature) {
      if (!fc.fixed[c] && at_c > kFlatAngle) on = c;
      else if (!fc.fixed[d] && at_d > kFlatAngle) on = d;
      if (on < 0) continue;  // a feature edge stays
    } else if (by_valence) {
      auto dev = [&](int32_t v, int delta) {
        const int x = valence[v] + delta - target[v];
        return x * x;
      };
      const int before = dev(a, 0) + dev(b, 0) + dev(c, 0) + dev(d, 0);
      const int after = dev(a, -1) + dev(b, -1) + dev(c, 1) + dev(d, 1);
      if (after >= before) continue;
    } else if (at_c + at_d <= M_PI + 1e-9) {
      continue;
    }
    if (!keeps_surface(fc, pa, pb, pc, pd, at_c, at_d)) continue;
    const double old_min = std::min(min_angle(pa, pb, pc), min_angle(pb, pa, pd));
    const double new_min = std::min(min_angle(pc, pa, pd), min_angle(pd, pb, pc));
    if (by_valence && on < 0 ? new_min < std::min(old_min, M_PI / 9) : new_min <= old_min) continue;
    if (on >= 0 && !fc.curves.adopt(m, a, b, on)) continue;
    --valence[a];
    --valence[b];
    ++valence[c];
    ++valence[d];
    F[fa] = {c, a, d};
    F[fb] = {d, b, c};
    ef.erase(it);
    ef[key(c, d)] = {fa, fb};
    auto& ad = ef[key(a, d)];
    (ad[0] == fb ? ad[0] : ad[1]) = fa;
    auto& bc = ef[key(b, c)];
    (bc[0] == fa ? bc[0] : bc[1]) = fb;
    if (on >= 0) fc.features.split(a, b, on), fc.fixed[on] = 1;
    ++flips;
  }
  return flips;
}

}  // namespace locus
