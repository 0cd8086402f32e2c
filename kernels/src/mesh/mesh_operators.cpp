// Discrete operators on triangle meshes: the cotan Laplacian L_C (thesis §3.3,
// eq. 3.5: (L_C)_ij = (cot a_ij + cot b_ij) / 2 with a negative diagonal), the
// lumped mass matrix (eq. 3.6: one third of the incident triangle areas), the heat
// operator M - t L_C (§3.3, §6.5 eq. 6.1), a regularized Laplacian for closed
// meshes, and vertex normals (area-weighted; mean-curvature normal -M^{-1} L_C p).
//
// All matrices share one lower CSC pattern: column j holds the diagonal j first,
// then the larger endpoints of the edges (j, k) in ascending k. Because the unique
// edges are sorted by (e0, e1), edge e lands at position e + e0[e] + 1, so the
// matrices are assembled directly in O(nnz) without triplets or sorting.
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/triangle_vector_area.hpp"
#include "locus/core/host_allocator.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/kernels/mesh/coordinate_range.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {

void require_triangles(const Mesh& m, const char* what) {
  validate_mesh_arrays(m);
  // A NaN or infinite coordinate would poison the mesh scale and every area after it;
  // name the vertex instead.
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (!std::isfinite(m.x[v]) || !std::isfinite(m.y[v]) || !std::isfinite(m.z[v]))
      fail(ErrorCode::BadInput, mesh_name(m) + ": vertex " + std::to_string(v) + " has a non-finite coordinate; " +
                                    what + " needs finite positions");
  check_mesh_size(m);  // areas and squared lengths representable (else every face looked degenerate)
  const int32_t nf = m.num_faces();
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t d = m.face_offsets[f + 1] - m.face_offsets[f];
    if (d != 3)
      fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has " + std::to_string(d) +
                                    " vertices; " + what + " needs a triangle mesh");
  }
}

struct CotanAndMass {
  CscMatrix L;
  HostVector<double> mass;
};

// One pass over the triangles: per corner, half the cotangent of its angle goes to
// the opposite edge; a third of the area goes to each vertex. The diagonal is minus
// the column sum so that L_C 1 = 0 holds to rounding.
CotanAndMass assemble_cotan_and_mass(const Mesh& m, const char* what, const EdgeIncidence* given = nullptr) {
  require_triangles(m, what);
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  if (given && given->corner_edge.size() != m.face_vertices.size())
    fail(ErrorCode::BadUsage, std::string(what) + ": the given edge incidence belongs to another mesh");
  EdgeIncidence own;
  if (!given) own = edge_incidence(m);
  const EdgeIncidence& inc = given ? *given : own;
  const Edges& E = inc.edges;
  const int64_t ne = static_cast<int64_t>(E.e0.size());
  const double h = mean_edge_length(m, E);
  const double sc = power_of_two_scale(h), inv_sc2 = 1.0 / (sc * sc);
  const double min_double_area = 2.0 * kDegenerateAreaRelative * (h * sc) * (h * sc);  // of the scaled triangle
  CotanAndMass out;
  out.L = operator_pattern(nv, E);
  out.mass.assign(static_cast<size_t>(nv), 0.0);
  double* val = out.L.values.data();
  const int32_t* fv = m.face_vertices.data();
  for (int32_t f = 0; f < nf; ++f) {
    cancel_point(f);
    const int32_t c0 = m.face_offsets[f];
    const int32_t v[3] = {fv[c0], fv[c0 + 1], fv[c0 + 2]};
    double px[3], py[3], pz[3];
    for (int k = 0; k < 3; ++k) {
      px[k] = m.x[v[k]] * sc;
      py[k] = m.y[v[k]] * sc;
      pz[k] = m.z[v[k]] * sc;
    }
    const double ux = px[1] - px[0], uy = py[1] - py[0], uz = pz[1] - pz[0];
    const double wx = px[2] - px[0], wy = py[2] - py[0], wz = pz[2] - pz[0];
    const double cx = uy * wz - uz * wy, cy = uz * wx - ux * wz, cz = ux * wy - uy * wx;
    const double double_area = std::sqrt(cx * cx + cy * cy + cz * cz);
    if (!(double_area > min_double_area) || !std::isfinite(double_area))
      fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has zero area; " + what +
                                    " needs non-degenerate triangles");
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      const double ax = px[k1] - px[k], ay = py[k1] - py[k], az = pz[k1] - pz[k];
      const double bx = px[k2] - px[k], by = py[k2] - py[k], bz = pz[k2] - pz[k];
      const double cot = (ax * bx + ay * by + az * bz) / double_area;  // cos/sin, |a x b| = 2 area
      const int32_t e = inc.corner_edge[c0 + k1];                       // edge opposite corner k
      val[e + E.e0[e] + 1] += 0.5 * cot;
      out.mass[v[k]] += double_area * inv_sc2 / 6.0;
    }
  }
  for (int64_t e = 0; e < ne; ++e) {
    const double w = val[e + E.e0[e] + 1];
    val[out.L.colptr[E.e0[e]]] -= w;
    val[out.L.colptr[E.e1[e]]] -= w;
  }
  return out;
}

CscMatrix with_diagonal(CscMatrix A, ConstView<double> d) {
  std::fill(A.values.begin(), A.values.end(), 0.0);
  for (int32_t j = 0; j < A.ncols; ++j) A.values[A.colptr[j]] = d[j];
  return A;
}

}  // namespace

CscMatrix operator_pattern(int32_t nv, const Edges& E) {
  const int64_t ne = static_cast<int64_t>(E.e0.size());
  CscMatrix A;
  A.nrows = A.ncols = nv;
  A.colptr.assign(static_cast<size_t>(nv) + 1, 0);
  for (int64_t e = 0; e < ne; ++e) ++A.colptr[E.e0[e] + 1];
  for (int32_t j = 0; j < nv; ++j) A.colptr[j + 1] += A.colptr[j] + 1;
  A.rowind.resize(static_cast<size_t>(nv + ne));
  A.values.assign(static_cast<size_t>(nv + ne), 0.0);
  for (int32_t j = 0; j < nv; ++j) A.rowind[A.colptr[j]] = j;
  for (int64_t e = 0; e < ne; ++e) A.rowind[e + E.e0[e] + 1] = E.e1[e];
  return A;
}

CscMatrix cotan_laplacian(const Mesh& m) { return assemble_cotan_and_mass(m, "the cotan Laplacian").L; }

HostVector<double> lumped_mass(const Mesh& m) {
  require_triangles(m, "the lumped mass matrix");
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  HostVector<double> mass(static_cast<size_t>(nv), 0.0);
  const int32_t* fv = m.face_vertices.data();
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t a = fv[3 * f], b = fv[3 * f + 1], c = fv[3 * f + 2];
    double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], uz = m.z[b] - m.z[a];
    double wx = m.x[c] - m.x[a], wy = m.y[c] - m.y[a], wz = m.z[c] - m.z[a];
    // Exact power-of-two scaling: no under/overflow in the squares at any mesh scale.
    const double sc = power_of_two_scale(std::max({std::abs(ux), std::abs(uy), std::abs(uz), std::abs(wx),
                                                   std::abs(wy), std::abs(wz)}));
    ux *= sc, uy *= sc, uz *= sc, wx *= sc, wy *= sc, wz *= sc;
    const double cx = uy * wz - uz * wy, cy = uz * wx - ux * wz, cz = ux * wy - uy * wx;
    const double third = std::sqrt(cx * cx + cy * cy + cz * cz) / (sc * sc) / 6.0;
    if (!std::isfinite(third))
      fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has a non-finite area");
    mass[a] += third;
    mass[b] += third;
    mass[c] += third;
  }
  return mass;
}

CscMatrix mass_matrix_as_csc(const Mesh& m) {
  validate_mesh_arrays(m);
  const HostVector<double> mass = lumped_mass(m);
  return with_diagonal(operator_pattern(m.num_vertices(), unique_edges(m)), mass);
}

CscMatrix heat_operator(const Mesh& m, double t, const EdgeIncidence* inc) {
  if (!(t >= 0.0) || !std::isfinite(t))
    fail(ErrorCode::BadUsage, "heat_operator: time step t must be finite and >= 0 (got " + std::to_string(t) + ")");
  CotanAndMass cm = assemble_cotan_and_mass(m, "the heat operator", inc);
  CscMatrix& A = cm.L;
  for (double& v : A.values) v *= -t;
  for (int32_t j = 0; j < A.ncols; ++j) A.values[A.colptr[j]] += cm.mass[j];
  return std::move(A);
}

CscMatrix regularized_laplacian(const Mesh& m, double rel, const EdgeIncidence* inc) {
  if (!(rel > 0.0) || !std::isfinite(rel))
    fail(ErrorCode::BadUsage, "regularized_laplacian: rel must be finite and > 0 (got " + std::to_string(rel) + ")");
  CotanAndMass cm = assemble_cotan_and_mass(m, "the regularized Laplacian", inc);
  CscMatrix& A = cm.L;
  double trace_l = 0.0, trace_m = 0.0;
  for (int32_t j = 0; j < A.ncols; ++j) {
    trace_l -= A.values[A.colptr[j]];
    trace_m += cm.mass[j];
  }
  if (!(trace_m > 0.0)) fail(ErrorCode::BadInput, mesh_name(m) + ": mesh has no area; cannot regularize");
  const double eps = rel * trace_l / trace_m;
  for (double& v : A.values) v = -v;
  for (int32_t j = 0; j < A.ncols; ++j) A.values[A.colptr[j]] += eps * cm.mass[j];
  return std::move(A);
}

std::array<double, 3> face_vector_area(const Mesh& m, int32_t f) {
  const auto fv = m.face(f);
  const int32_t o = fv[0];
  double ax = 0, ay = 0, az = 0;
  for (size_t c = 1; c + 1 < fv.size(); ++c) {
    const std::array<double, 3> t = triangle_vector_area(m, o, fv[c], fv[c + 1]);
    ax += t[0];
    ay += t[1];
    az += t[2];
  }
  return {ax, ay, az};
}

HostVector<double> area_weighted_normals(const Mesh& m) {
  validate_mesh_arrays(m);
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  HostVector<double> n(3 * static_cast<size_t>(nv), 0.0);
  const int32_t* fv = m.face_vertices.data();
  for (int32_t f = 0; f < nf; ++f) {
    const auto [ax, ay, az] = face_vector_area(m, f);
    const int32_t b = m.face_offsets[f], e = m.face_offsets[f + 1];
    for (int32_t c = b; c < e; ++c) {
      const size_t v = static_cast<size_t>(fv[c]);
      n[3 * v] += ax;
      n[3 * v + 1] += ay;
      n[3 * v + 2] += az;
    }
  }
  for (size_t v = 0; v < static_cast<size_t>(nv); ++v) {
    const double len = std::sqrt(n[3 * v] * n[3 * v] + n[3 * v + 1] * n[3 * v + 1] + n[3 * v + 2] * n[3 * v + 2]);
    if (len > 0.0 && std::isfinite(len))
      for (int k = 0; k < 3; ++k) n[3 * v + k] /= len;
    else
      for (int k = 0; k < 3; ++k) n[3 * v + k] = 0.0;  // unreferenced vertex or cancelling faces
  }
  return n;
}

HostVector<double> mean_curvature_normals(const Mesh& m, const EdgeIncidence* inc) {
  const CotanAndMass cm = assemble_cotan_and_mass(m, "the mean-curvature normal", inc);
  const int32_t nv = m.num_vertices();
  HostVector<double> hn(3 * static_cast<size_t>(nv), 0.0);
  const CscMatrix& L = cm.L;
  const HostVector<double>* coords[3] = {&m.x, &m.y, &m.z};
  for (int k = 0; k < 3; ++k) {
    const HostVector<double>& p = *coords[k];
    // (L p)_i = sum_j w_ij (p_j - p_i): written with differences so that a far-away
    // origin does not cancel digits.
    HostVector<double> lp(static_cast<size_t>(nv), 0.0);
    for (int32_t j = 0; j < nv; ++j)
      for (int64_t q = L.colptr[j] + 1; q < L.colptr[j + 1]; ++q) {
        const int32_t i = L.rowind[q];
        const double w = L.values[q];
        lp[i] += w * (p[j] - p[i]);
        lp[j] += w * (p[i] - p[j]);
      }
    for (int32_t i = 0; i < nv; ++i)
      hn[3 * static_cast<size_t>(i) + k] = cm.mass[i] > 0.0 ? -lp[i] / cm.mass[i] : 0.0;
  }
  return hn;
}

}  // namespace locus
