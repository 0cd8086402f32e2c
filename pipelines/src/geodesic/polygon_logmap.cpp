// Log map on polygon meshes (pipelines/include/locus/pipelines/geodesic/polygon_logmap.hpp; thesis §6.5-6.6).
#include "locus/pipelines/geodesic/polygon_logmap.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/error.hpp"

namespace locus {

namespace {
inline double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
}  // namespace

PolygonLogMap::PolygonLogMap(const Mesh& m, const PolygonHeatGeodesicOptions& opt, const RunContext& ctx)
    : geo_(m, opt, ctx), n_(m.num_vertices()) {
  vf_offsets_.assign(static_cast<size_t>(n_) + 1, 0);
  for (int32_t v : m.face_vertices) ++vf_offsets_[v + 1];
  for (int32_t i = 0; i < n_; ++i) vf_offsets_[i + 1] += vf_offsets_[i];
  vf_faces_.resize(m.face_vertices.size());
  std::vector<int32_t> fill(vf_offsets_.begin(), vf_offsets_.end() - 1);
  for (int32_t f = 0; f < m.num_faces(); ++f)
    for (int32_t q = m.face_offsets[f]; q < m.face_offsets[f + 1]; ++q) vf_faces_[fill[m.face_vertices[q]]++] = f;
}

void PolygonLogMap::query_full(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out) const {
  const size_t np = patch.size();
  if (out.distance.size() != np || out.angle.size() != np || out.u.size() != np || out.v.size() != np)
    fail(ErrorCode::BadUsage, "log map: every output span needs one entry per patch vertex (" + std::to_string(np) + ")");
  if (center < 0 || center >= n_) fail(ErrorCode::BadUsage, "center " + std::to_string(center) + " is not a vertex");
  bool has_center = false;
  for (int32_t v : patch) {
    if (v < 0 || v >= n_) fail(ErrorCode::BadUsage, "patch vertex " + std::to_string(v) + " is out of range");
    has_center |= v == center;
  }
  if (!has_center) fail(ErrorCode::BadUsage, "the center vertex " + std::to_string(center) + " is not in the patch");
  // Sources: the center, then the corners of its faces, ascending.
  std::vector<int32_t> S;
  for (int32_t q = vf_offsets_[center]; q < vf_offsets_[center + 1]; ++q)
    for (int32_t w : geo_.face(vf_faces_[q]))
      if (w != center) S.push_back(w);
  std::sort(S.begin(), S.end());
  S.erase(std::unique(S.begin(), S.end()), S.end());
  if (S.empty()) fail(ErrorCode::BadInput, "log map: the center " + std::to_string(center) + " is in no face");
  S.insert(S.begin(), center);
  const size_t d = S.size();
  auto slot = [&](int32_t w) { return static_cast<size_t>(std::find(S.begin(), S.end(), w) - S.begin()); };
  // Frame and estimator coefficients from the fan triangles around the center.
  const Mesh& R = geo_.refined();
  const TriangleGradients& g = geo_.gradients();
  double nrm[3] = {0, 0, 0};
  std::vector<double> W(3 * d, 0.0);
  for (int64_t q = g.vf_offsets[center]; q < g.vf_offsets[center + 1]; ++q) {
    const int32_t f = g.vf_faces[q];
    const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(f);
    const double ax = R.x[t[1]] - R.x[t[0]], ay = R.y[t[1]] - R.y[t[0]], az = R.z[t[1]] - R.z[t[0]];
    const double bx = R.x[t[2]] - R.x[t[0]], by = R.y[t[2]] - R.y[t[0]], bz = R.z[t[2]] - R.z[t[0]];
    nrm[0] += ay * bz - az * by, nrm[1] += az * bx - ax * bz, nrm[2] += ax * by - ay * bx;
    const double* bs = g.basis.data() + 9 * static_cast<int64_t>(f);
    for (int s = 0; s < 3; ++s) {
      auto add = [&](int32_t w, double weight) {
        const size_t k = slot(w);
        for (int c = 0; c < 3; ++c) W[3 * k + c] += g.area[f] * weight * bs[3 * s + c];
      };
      if (t[s] < n_) {
        add(t[s], 1.0);
      } else {
        const std::span<const int32_t> fc = geo_.face(geo_.face_of_virtual(t[s]));
        for (int32_t w : fc) add(w, 1.0 / static_cast<double>(fc.size()));
      }
    }
  }
  const double nl = std::sqrt(dot3(nrm, nrm));
  for (double& c : nrm) c /= nl;
  const int32_t ref = S[1];  // the lowest-numbered neighbor
  double e1[3] = {R.x[ref] - R.x[center], R.y[ref] - R.y[center], R.z[ref] - R.z[center]};
  const double en = dot3(e1, nrm);
  for (int c = 0; c < 3; ++c) e1[c] -= en * nrm[c];
  const double el = std::sqrt(dot3(e1, e1));
  for (double& c : e1) c /= el;
  const double e2[3] = {nrm[1] * e1[2] - nrm[2] * e1[1], nrm[2] * e1[0] - nrm[0] * e1[2], nrm[0] * e1[1] - nrm[1] * e1[0]};
  std::vector<double> a(d), b(d);
  for (size_t k = 0; k < d; ++k) a[k] = dot3(&W[3 * k], e1), b[k] = dot3(&W[3 * k], e2);
  // The heat from every source (full solves), the distance from lane 0.
  std::vector<double> heat(d * static_cast<size_t>(n_), 0.0), dist(static_cast<size_t>(n_));
  for (size_t k = 0; k < d; ++k) {
    const std::span<double> h(heat.data() + k * n_, static_cast<size_t>(n_));
    h[S[k]] = 1.0;
    geo_.solve_heat(h);
  }
  geo_.distance_from_heat(std::span<const double>(heat.data(), static_cast<size_t>(n_)), center, dist);
  for (size_t p = 0; p < np; ++p) {
    const int32_t j = patch[p];
    out.distance[p] = dist[j];
    double gx = 0, gy = 0;
    bool positive = true;
    for (size_t k = 0; k < d; ++k) positive &= heat[k * n_ + j] > 0;
    for (size_t k = 0; k < d; ++k) {
      const double f = positive ? std::log(heat[k * n_ + j]) : heat[k * n_ + j];
      gx += a[k] * f;
      gy += b[k] * f;
    }
    const double th = j == center || (gx == 0 && gy == 0) ? 0.0 : std::atan2(gy, gx);
    out.angle[p] = th;
    out.u[p] = j == center ? 0.0 : dist[j] * std::cos(th);
    out.v[p] = j == center ? 0.0 : dist[j] * std::sin(th);
  }
}

int64_t count_flipped_polygons(const Mesh& m, std::span<const int32_t> patch, std::span<const double> u,
                               std::span<const double> v) {
  std::vector<int32_t> local(static_cast<size_t>(m.num_vertices()), -1);
  for (size_t p = 0; p < patch.size(); ++p) local[patch[p]] = static_cast<int32_t>(p);
  int64_t flipped = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const ConstView<int32_t> fc = m.face(f);
    bool inside = true;
    for (int32_t w : fc) inside &= local[w] >= 0;
    if (!inside) continue;
    const int32_t o = local[fc[0]];
    for (size_t s = 1; s + 1 < fc.size(); ++s) {
      const int32_t p1 = local[fc[s]], p2 = local[fc[s + 1]];
      if ((u[p1] - u[o]) * (v[p2] - v[o]) - (u[p2] - u[o]) * (v[p1] - v[o]) < 0) {
        ++flipped;
        break;
      }
    }
  }
  return flipped;
}

}  // namespace locus
