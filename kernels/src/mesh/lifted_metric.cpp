// Edge-length operators of a mesh with positions in R^d and the R^6 lift of the
// anisotropic CVT (kernels/include/locus/kernels/mesh/lifted_metric.hpp; thesis §3.7.1,
// §3.3 eqs. 3.5-3.6).
#include "locus/kernels/mesh/lifted_metric.hpp"
#include "locus/core/host_allocator.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

namespace {

void check_positions(const Mesh& m, std::span<const double> pos, int dim, const char* what) {
  if (dim < 1 || pos.size() != static_cast<size_t>(m.num_vertices()) * dim)
    fail(ErrorCode::BadUsage, std::string(what) + ": expected " + std::to_string(dim) + " values per vertex");
}

// |pos_a - pos_b|^2 in `dim` dimensions, summed in coordinate order.
double squared_distance(std::span<const double> pos, int dim, int32_t a, int32_t b) {
  double s = 0;
  for (int c = 0; c < dim; ++c) {
    const double d = pos[static_cast<size_t>(a) * dim + c] - pos[static_cast<size_t>(b) * dim + c];
    s += d * d;
  }
  return s;
}

}  // namespace

double triangle_area_from_squared_lengths(double l2a, double l2b, double l2c) {
  double l[3] = {std::sqrt(l2a), std::sqrt(l2b), std::sqrt(l2c)};
  std::sort(l, l + 3, std::greater<double>());
  const double a = l[0], b = l[1], c = l[2];  // a >= b >= c: Kahan's ordering
  const double q = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return q > 0 ? 0.25 * std::sqrt(q) : 0.0;
}

HostVector<double> face_areas_from_positions(const Mesh& m, std::span<const double> pos, int dim) {
  const int32_t nf = m.num_faces();
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": face areas need a triangle mesh");
  check_positions(m, pos, dim, "face areas");
  HostVector<double> area(nf);
  for (int32_t f = 0; f < nf; ++f)
    area[f] = triangle_area_from_squared_lengths(squared_distance(pos, dim, m.f1[f], m.f2[f]),
                                                 squared_distance(pos, dim, m.f2[f], m.f0[f]),
                                                 squared_distance(pos, dim, m.f0[f], m.f1[f]));
  return area;
}

HostVector<double> face_areas(const Mesh& m) {
  HostVector<double> p(3 * static_cast<size_t>(m.num_vertices()));
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    p[3 * static_cast<size_t>(v)] = m.x[v];
    p[3 * static_cast<size_t>(v) + 1] = m.y[v];
    p[3 * static_cast<size_t>(v) + 2] = m.z[v];
  }
  return face_areas_from_positions(m, p, 3);
}

CscMatrix heat_operator_from_positions(const Mesh& m, std::span<const double> pos, int dim, double t,
                                       HostVector<double>& mass, double& mean_edge) {
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  check_positions(m, pos, dim, "heat operator from positions");
  mass.assign(n, 0.0);
  std::vector<int32_t> ii, jj;
  std::vector<double> vv;
  ii.reserve(static_cast<size_t>(n) + 3 * static_cast<size_t>(nf));
  jj.reserve(ii.capacity());
  vv.reserve(ii.capacity());
  std::vector<double> diag(n, 0.0);
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    // l2[k]: squared length of the edge opposite corner k.
    const double l2[3] = {squared_distance(pos, dim, v[1], v[2]), squared_distance(pos, dim, v[2], v[0]),
                          squared_distance(pos, dim, v[0], v[1])};
    const double area = triangle_area_from_squared_lengths(l2[0], l2[1], l2[2]);
    if (!(area > 0) || !std::isfinite(area))
      fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has zero area in the lifted metric");
    for (int k = 0; k < 3; ++k) {
      mass[v[k]] += area / 3;
      const int32_t i = v[(k + 1) % 3], j = v[(k + 2) % 3];
      const double w = 0.5 * (l2[(k + 1) % 3] + l2[(k + 2) % 3] - l2[k]) / (4 * area);  // cot at k, halved
      ii.push_back(i);
      jj.push_back(j);
      vv.push_back(-t * w);
      diag[i] += t * w;
      diag[j] += t * w;
    }
  }
  for (int32_t v = 0; v < n; ++v) {
    ii.push_back(v);
    jj.push_back(v);
    vv.push_back(mass[v] + diag[v]);
  }
  const Edges e = unique_edges(m);
  double sum = 0;
  for (size_t k = 0; k < e.e0.size(); ++k) sum += std::sqrt(squared_distance(pos, dim, e.e0[k], e.e1[k]));
  mean_edge = e.e0.empty() ? 0.0 : sum / static_cast<double>(e.e0.size());
  return lower_from_triplets(n, ii, jj, vv);
}

std::vector<double> lifted_positions(const Mesh& m, double lambda) {
  const int32_t n = m.num_vertices();
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  const HostVector<double>* X[3] = {&m.x, &m.y, &m.z};
  for (int c = 0; c < 3; ++c)
    for (int32_t v = 0; v < n; ++v) {
      lo[c] = std::min(lo[c], (*X[c])[v]);
      hi[c] = std::max(hi[c], (*X[c])[v]);
    }
  const double side = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!(side > 0) || !std::isfinite(side)) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no extent");
  const HostVector<double> nrm = area_weighted_normals(m);
  std::vector<double> p(static_cast<size_t>(n) * 6);
  for (int32_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) {
      p[6 * static_cast<size_t>(v) + c] = ((*X[c])[v] - lo[c]) / side;
      p[6 * static_cast<size_t>(v) + 3 + c] = lambda * nrm[3 * static_cast<size_t>(v) + c];
    }
  return p;
}

}  // namespace locus
