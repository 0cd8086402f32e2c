// The heat log map's per-vertex geometry (pipelines/include/locus/pipelines/geodesic/logmap.hpp;
// thesis §6.5, eq. 6.2): vertex normals and tangent frames, and the classes of
// a center's star (irregular, lattice defect) by which the Auto estimator
// chooses (logmap_estimator.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "logmap_parts.hpp"

namespace locus {

namespace {
// |H n| below this times 1 / h means a curvature radius above 1e8 h: numerically planar.
constexpr double kPlanarCurvature = 1e-8;
// A star is irregular when a corner angle at its vertex is off the regular
// value 2 pi / valence by more than kIrregularAngle (relative) or its longest
// edge exceeds kIrregularEdgeRatio times its shortest. Icospheres of any level
// stay well inside (angles within ~15 %, edge ratio < 1.3); convex hulls of
// random points mostly do not.
constexpr double kIrregularAngle = 0.25;
constexpr double kIrregularEdgeRatio = 1.6;
// The valence of an interior vertex of the triangle lattice.
constexpr int64_t kLatticeValence = 6;
}  // namespace

HeatLogMap::HeatLogMap(const Mesh& m, const LogMapOptions& opt, const RunContext& ctx, const MeshDerived* derived)
    : opt_(opt), geo_(m, opt.geodesic, ctx, derived), x_(m.x), y_(m.y), z_(m.z) {
  prepare(m, derived);
}

HeatLogMap::HeatLogMap(const Mesh& m, const LogMapOptions& opt, HeatGeodesicFactors factors)
    : opt_(opt), geo_(m, opt.geodesic, std::move(factors)), x_(m.x), y_(m.y), z_(m.z) {
  prepare(m);
}

void HeatLogMap::prepare(const Mesh& m, const MeshDerived* derived) {
  const int32_t n = m.num_vertices();
  // Eq. 6.2: the mean-curvature normal where it is meaningful, the area normal
  // where it vanishes (planar regions) and at boundary vertices (where L_C p has
  // an in-plane boundary term). Oriented to the side of the face normals so that
  // the map keeps the faces' orientation.
  EdgeIncidence own;
  if (!derived) own = edge_incidence(m);
  const EdgeIncidence& inc = derived ? derived->incidence : own;
  const HostVector<double> hn = mean_curvature_normals(m, &inc);
  const HostVector<double> an = area_weighted_normals(m);
  const Edges& e = inc.edges;
  HostVector<uint8_t>& boundary = boundary_;
  boundary.assign(static_cast<size_t>(n), 0);
  for (size_t k = 0; k < e.e0.size(); ++k)
    if (e.face_count[k] == 1) boundary[e.e0[k]] = boundary[e.e1[k]] = 1;
  const double tiny = kPlanarCurvature / geo_.mean_edge_length();
  normal_.resize(3 * static_cast<size_t>(n));
  for (int32_t i = 0; i < n; ++i) {
    const double* h = hn.data() + 3 * static_cast<size_t>(i);
    const double* a = an.data() + 3 * static_cast<size_t>(i);
    const double len = std::sqrt(dot3(h, h));
    double* o = normal_.data() + 3 * static_cast<size_t>(i);
    if (!boundary[i] && len > tiny && std::isfinite(len)) {
      const double s = dot3(h, a) < 0 ? -1.0 / len : 1.0 / len;
      for (int c = 0; c < 3; ++c) o[c] = h[c] * s;
    } else {
      for (int c = 0; c < 3; ++c) o[c] = a[c];
    }
  }
}

void HeatLogMap::frame(int32_t i, double n[3], double e1[3], double e2[3]) const {
  const TriangleGradients& g = geo_.gradients();
  for (int c = 0; c < 3; ++c) n[c] = normal_[3 * static_cast<size_t>(i) + c];
  // Lowest-numbered neighbor: deterministic, independent of face order.
  int32_t ref = -1;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q)
    for (int s = 0; s < 3; ++s) {
      const int32_t w = g.tri[3 * static_cast<int64_t>(g.vf_faces[q]) + s];
      if (w != i && (ref < 0 || w < ref)) ref = w;
    }
  double d[3] = {x_[ref] - x_[i], y_[ref] - y_[i], z_[ref] - z_[i]};
  const double dn = dot3(d, n);
  for (int c = 0; c < 3; ++c) d[c] -= dn * n[c];
  const double len = std::sqrt(dot3(d, d));
  for (int c = 0; c < 3; ++c) e1[c] = d[c] / len;
  e2[0] = n[1] * e1[2] - n[2] * e1[1];
  e2[1] = n[2] * e1[0] - n[0] * e1[2];
  e2[2] = n[0] * e1[1] - n[1] * e1[0];
}

// Corner angles against their mean (the regular value), edge lengths against
// each other; see kIrregularAngle.
bool HeatLogMap::irregular_star(int32_t i) const {
  const TriangleGradients& g = geo_.gradients();
  const int64_t valence = g.vf_offsets[i + 1] - g.vf_offsets[i];
  if (valence < 3) return false;
  // The two edges from i in the corner of i's q-th face.
  auto corner = [&](int64_t q, double u[3], double w[3]) {
    int32_t a, b;
    star_corner(g, g.vf_faces[q], i, a, b);
    u[0] = x_[a] - x_[i], u[1] = y_[a] - y_[i], u[2] = z_[a] - z_[i];
    w[0] = x_[b] - x_[i], w[1] = y_[b] - y_[i], w[2] = z_[b] - z_[i];
  };
  double total = 0, lmin = std::numeric_limits<double>::infinity(), lmax = 0;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
    double u[3], w[3];
    corner(q, u, w);
    const double lu = std::sqrt(dot3(u, u)), lw = std::sqrt(dot3(w, w));
    lmin = std::min({lmin, lu, lw});
    lmax = std::max({lmax, lu, lw});
    total += std::acos(std::clamp(dot3(u, w) / (lu * lw), -1.0, 1.0));
  }
  const double regular = total / static_cast<double>(valence);
  double worst = 0;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
    double u[3], w[3];
    corner(q, u, w);
    const double ang = std::acos(std::clamp(dot3(u, w) / std::sqrt(dot3(u, u) * dot3(w, w)), -1.0, 1.0));
    worst = std::max(worst, std::abs(ang - regular) / regular);
  }
  return worst > kIrregularAngle || lmax > kIrregularEdgeRatio * lmin;
}

// A lattice defect: an interior vertex whose valence is not the triangle
// lattice's 6 (an icosphere's 12 corners: valence 5, a cone of the lattice;
// such stars may still be regular in shape). The lattice corrections model
// the heat's anisotropy along straight rays through a lattice; around a cone
// the rays bend and the correction made things worse (icosphere 7, vertex 0:
// Path 4.35e-3 against 3.19e-3 uncorrected at t = h^2, 1.22e-3 against 0.95e-3
// at 4 h^2; also without the center's own star in the Path sums:
// docs/logmap.md, "Defect centers"), so they apply at valence-6 stars only.
bool HeatLogMap::defect_star(int32_t i) const {
  const TriangleGradients& g = geo_.gradients();
  return g.vf_offsets[i + 1] - g.vf_offsets[i] != kLatticeValence && !boundary_[i];
}

}  // namespace locus
