// The tufted cover of a triangle soup (Sharp & Crane, "A Laplacian for
// Nonmanifold Triangle Meshes", SGP 2020, §4.2; thesis §3.3 for the operators
// built on it): two oppositely oriented copies of every triangle, glued in pairs
// around each edge. The gluing is read off the mesh's edge incidence (one bucket
// sort, mesh_topology.hpp), so the cover costs O(nv + nf).
#include "locus/kernels/mesh/tufted_cover.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

namespace {

void require_finite_triangles(const Mesh& m) {
  validate_mesh_arrays(m);
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (!std::isfinite(m.x[v]) || !std::isfinite(m.y[v]) || !std::isfinite(m.z[v]))
      fail(ErrorCode::BadInput, mesh_name(m) + ": vertex " + std::to_string(v) +
                                    " has a non-finite coordinate; the robust Laplacian needs finite positions");
  for (int32_t f = 0; f < m.num_faces(); ++f)
    if (m.face_offsets[f + 1] - m.face_offsets[f] != 3)
      fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has " +
                                    std::to_string(m.face_offsets[f + 1] - m.face_offsets[f]) +
                                    " vertices; the robust Laplacian needs a triangle mesh");
}

double distance(const Mesh& m, int32_t a, int32_t b) {
  double d[3] = {m.x[b] - m.x[a], m.y[b] - m.y[a], m.z[b] - m.z[a]};
  const double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  // Fast path unless the squares may have underflowed or overflowed; then scaled
  // by a power of two (exact).
  if (d2 > 1e-200 && d2 < 1e200) return std::sqrt(d2);
  const double sc = power_of_two_scale(std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])}));
  for (double& c : d) c *= sc;
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / sc;
}

}  // namespace

IntrinsicTriangulation tufted_cover(const Mesh& m) {
  require_finite_triangles(m);
  const int32_t nf = m.num_faces();
  const int32_t* fv = m.face_vertices.data();
  IntrinsicTriangulation T;
  T.num_vertices = m.num_vertices();
  // kept[f]: index q of f among the kept triangles, or -1.
  std::vector<int32_t> kept(static_cast<size_t>(nf), -1);
  int32_t nk = 0;
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t a = fv[3 * f], b = fv[3 * f + 1], c = fv[3 * f + 2];
    if (a != b && b != c && c != a) kept[f] = nk++;
  }
  T.vertex.resize(6 * static_cast<size_t>(nk));
  T.twin.assign(6 * static_cast<size_t>(nk), -1);
  T.length.resize(6 * static_cast<size_t>(nk));
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t q = kept[f];
    if (q < 0) continue;
    const int32_t a = fv[3 * f], b = fv[3 * f + 1], c = fv[3 * f + 2];
    const int32_t front = 6 * q, back = 6 * q + 3;  // (a, b, c) and (a, c, b)
    const int32_t fr[3] = {a, b, c}, bk[3] = {a, c, b};
    for (int k = 0; k < 3; ++k) {
      T.vertex[front + k] = fr[k];
      T.vertex[back + k] = bk[k];
      // Front side k (fr[k] -> fr[k+1]) is back side 2 - k run the other way.
      const double len = distance(m, fr[k], fr[(k + 1) % 3]);
      T.length[front + k] = len;
      T.length[back + 2 - k] = len;
    }
  }
  // Around each edge: the sides of its kept triangles in face order; the copy
  // running e0 -> e1 of triangle i meets the copy running e1 -> e0 of triangle i+1.
  const EdgeIncidence inc = edge_incidence(m);
  const int64_t ne = static_cast<int64_t>(inc.edges.e0.size());
  std::vector<int32_t> forward, backward;
  for (int64_t e = 0; e < ne; ++e) {
    forward.clear();
    backward.clear();
    for (int64_t p = inc.edge_corner_offsets[e]; p < inc.edge_corner_offsets[e + 1]; ++p) {
      const int32_t c = inc.edge_corners[p], f = c / 3, k = c % 3;
      const int32_t q = kept[f];
      if (q < 0) continue;
      const int32_t front = 6 * q + k, back = 6 * q + 3 + (2 - k);
      const bool front_forward = fv[c] == inc.edges.e0[e];
      forward.push_back(front_forward ? front : back);
      backward.push_back(front_forward ? back : front);
    }
    const size_t k = forward.size();
    for (size_t i = 0; i < k; ++i) {
      const int32_t s = forward[i], t = backward[(i + 1) % k];
      T.twin[s] = t;
      T.twin[t] = s;
    }
  }
  return T;
}

}  // namespace locus
