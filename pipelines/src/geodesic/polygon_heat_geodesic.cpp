// Heat geodesic distance on polygon meshes (pipelines/include/locus/pipelines/geodesic/polygon_heat_geodesic.hpp;
// thesis §6.4.1 on the virtual-vertex polygon operators).
#include "locus/pipelines/geodesic/polygon_heat_geodesic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

namespace {

// Mean length of the polygon edges, each undirected edge once.
double mean_polygon_edge(const Mesh& m) {
  std::vector<std::pair<int32_t, int32_t>> e;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t b = m.face_offsets[f], k = m.face_offsets[f + 1] - b;
    for (int32_t s = 0; s < k; ++s) {
      const int32_t u = m.face_vertices[b + s], v = m.face_vertices[b + (s + 1) % k];
      e.emplace_back(std::min(u, v), std::max(u, v));
    }
  }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  double sum = 0;
  for (auto [u, v] : e) sum += std::hypot(m.x[u] - m.x[v], m.y[u] - m.y[v], m.z[u] - m.z[v]);
  return e.empty() ? 0.0 : sum / static_cast<double>(e.size());
}

}  // namespace

PolygonHeatGeodesic::PolygonHeatGeodesic(const Mesh& m, const PolygonHeatGeodesicOptions& opt, const RunContext& ctx)
    : n_(m.num_vertices()), face_offsets_(m.face_offsets), face_vertices_(m.face_vertices) {
  if (!(opt.t_factor > 0) || !std::isfinite(opt.t_factor) || !(opt.poisson_rel > 0))
    fail(ErrorCode::BadUsage, "polygon heat geodesic: t_factor and poisson_rel must be finite positive numbers");
  if (n_ == 0 || m.num_faces() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no faces");
  // The refined mesh: the vertices, one virtual vertex per face of k > 3 corners, the fans.
  refined_.x = m.x;
  refined_.y = m.y;
  refined_.z = m.z;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t b = m.face_offsets[f], k = m.face_offsets[f + 1] - b;
    if (k < 3) fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has fewer than 3 corners");
    const int32_t* fv = m.face_vertices.data() + b;
    if (k == 3) {
      refined_.add_triangle(fv[0], fv[1], fv[2]);
      continue;
    }
    double c[3] = {0, 0, 0};
    for (int32_t s = 0; s < k; ++s) c[0] += m.x[fv[s]], c[1] += m.y[fv[s]], c[2] += m.z[fv[s]];
    const int32_t v = refined_.num_vertices();
    refined_.add_vertex(c[0] / k, c[1] / k, c[2] / k);
    face_of_virtual_.push_back(f);
    for (int32_t s = 0; s < k; ++s) refined_.add_triangle(fv[s], fv[(s + 1) % k], v);
  }
  h_ = mean_polygon_edge(m);
  t_ = opt.t_factor * h_ * h_;
  grad_ = triangle_gradients(refined_);  // (BadInput on zero-area fan triangles)
  // L = P^T L_C P (lower triplets; see the header) and M = P^T m.
  const CscMatrix Lr = cotan_laplacian(refined_);
  const auto mr = lumped_mass(refined_);
  auto row = [&](int32_t r, auto&& fn) {  // the entries (vertex, weight) of row r of P
    if (r < n_) return fn(r, 1.0);
    const int32_t f = face_of_virtual_[r - n_], b = face_offsets_[f], k = face_offsets_[f + 1] - b;
    for (int32_t s = 0; s < k; ++s) fn(face_vertices_[b + s], 1.0 / k);
  };
  std::vector<int32_t> ii, jj;
  std::vector<double> vv;
  for (int32_t c = 0; c < Lr.ncols; ++c)
    for (int64_t q = Lr.colptr[c]; q < Lr.colptr[c + 1]; ++q) {
      const int32_t r = Lr.rowind[q];
      const double val = Lr.values[q];
      row(r, [&](int32_t a, double wa) {
        row(c, [&](int32_t b, double wb) {
          // Off the stored diagonal the (c, r) mirror adds the same product once
          // more; on it, each unordered pair is met twice (a, b) and (b, a).
          if (r != c) {
            ii.push_back(a), jj.push_back(b), vv.push_back(val * wa * wb * (a == b ? 2.0 : 1.0));
          } else if (a >= b) {
            ii.push_back(a), jj.push_back(b), vv.push_back(val * wa * wb);
          }
        });
      });
    }
  const CscMatrix L = lower_from_triplets(n_, ii, jj, vv);
  std::vector<double> mass(static_cast<size_t>(n_), 0.0);
  restrict_add(mr, mass);
  double trace = 0, area = 0;
  for (int32_t j = 0; j < n_; ++j) {
    if (L.colptr[j] == L.colptr[j + 1] || L.rowind[L.colptr[j]] != j)
      fail(ErrorCode::BadInput, mesh_name(m) + ": vertex " + std::to_string(j) + " is in no face");
    trace -= L.values[L.colptr[j]];
    area += mass[j];
  }
  const double eps = opt.poisson_rel * trace / n_ / area;
  CscMatrix A = L, P = L;
  for (double& x : A.values) x = -t_ * x;
  for (double& x : P.values) x = -x;
  for (int32_t j = 0; j < n_; ++j) {
    A.values[A.colptr[j]] += mass[j];
    P.values[P.colptr[j]] += eps * mass[j];
  }
  const auto S = analyze(A, order_matrix(A, {}, ctx));
  heat_ = factorize(S, A, ctx.sub(0.5, 0.75));
  poisson_ = factorize(S, P, ctx.sub(0.75, 1.0));
}

void PolygonHeatGeodesic::prolong(std::span<const double> x, std::vector<double>& y) const {
  y.assign(x.begin(), x.end());
  for (int32_t f : face_of_virtual_) {
    const int32_t b = face_offsets_[f], k = face_offsets_[f + 1] - b;
    double s = 0;
    for (int32_t q = 0; q < k; ++q) s += x[face_vertices_[b + q]];
    y.push_back(s / k);
  }
}

void PolygonHeatGeodesic::restrict_add(std::span<const double> y, std::span<double> x) const {
  for (int32_t i = 0; i < n_; ++i) x[i] += y[i];
  for (size_t v = 0; v < face_of_virtual_.size(); ++v) {
    const int32_t f = face_of_virtual_[v], b = face_offsets_[f], k = face_offsets_[f + 1] - b;
    for (int32_t q = 0; q < k; ++q) x[face_vertices_[b + q]] += y[static_cast<size_t>(n_) + v] / k;
  }
}

void PolygonHeatGeodesic::query_full(int32_t source, std::span<double> distance) const {
  if (source < 0 || source >= n_)
    fail(ErrorCode::BadUsage, "source " + std::to_string(source) + " is not a vertex (the mesh has " +
                                  std::to_string(n_) + " vertices)");
  if (distance.size() != static_cast<size_t>(n_))
    fail(ErrorCode::BadUsage, "polygon heat geodesic: distance needs one entry per vertex");
  std::vector<double> h(static_cast<size_t>(n_), 0.0);
  h[source] = 1.0;
  solve_heat(h);
  distance_from_heat(h, source, distance);
}

void PolygonHeatGeodesic::solve_heat(std::span<double> h) const {
  std::vector<double> work(solve_work_size(heat_, 1));
  solve(heat_, h, work);
}

void PolygonHeatGeodesic::distance_from_heat(std::span<const double> h, int32_t source,
                                             std::span<double> distance) const {
  std::vector<double> hr;
  // log h is what is nearly linear (HeatGeodesicOptions::log_heat_gradient), so
  // it is log h that P interpolates: the mean of the corners' heat would make
  // every face center hotter than the log-linear heat (Jensen) and bend X
  // towards it. Where a corner is not positive: h itself.
  std::vector<double> lh(h.size()), lr, bad(h.size()), badr;
  for (size_t i = 0; i < h.size(); ++i) {
    lh[i] = h[i] > 0 ? std::log(h[i]) : 0.0;
    bad[i] = h[i] > 0 ? 0.0 : 1.0;
  }
  prolong(h, hr);
  prolong(lh, lr);
  prolong(bad, badr);  // > 0 where some corner's heat is not positive
  // Per fan triangle: X = -grad log h / |.| (grad h where a corner is not positive), then D X.
  std::vector<double> br(hr.size(), 0.0);
  for (int32_t f = 0; f < grad_.nf; ++f) {
    const int32_t* t = grad_.tri.data() + 3 * static_cast<int64_t>(f);
    const double u[3] = {hr[t[0]], hr[t[1]], hr[t[2]]};
    double X[3];
    if (badr[t[0]] == 0 && badr[t[1]] == 0 && badr[t[2]] == 0) grad_.gradient(f, lr[t[0]], lr[t[1]], lr[t[2]], X);
    else grad_.gradient(f, u[0], u[1], u[2], X);
    const double len = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
    const double sc = len > 0 && std::isfinite(len) ? -1.0 / len : 0.0;
    const double* bs = grad_.basis.data() + 9 * static_cast<int64_t>(f);
    for (int s = 0; s < 3; ++s)
      br[t[s]] += grad_.area[f] * sc * (bs[3 * s] * X[0] + bs[3 * s + 1] * X[1] + bs[3 * s + 2] * X[2]);
  }
  std::vector<double> b(static_cast<size_t>(n_), 0.0);
  restrict_add(br, b);
  std::vector<double> work(solve_work_size(poisson_, 1));
  solve(poisson_, b, work);
  for (int32_t i = 0; i < n_; ++i) distance[i] = b[i] - b[source];
}

}  // namespace locus
