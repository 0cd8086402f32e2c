// Per-triangle gradient basis (kernels/include/locus/kernels/mesh/mesh_gradient.hpp; thesis eq. 6.4).
#include "locus/kernels/mesh/mesh_gradient.hpp"
#include "locus/core/host_allocator.hpp"

#include <cmath>
#include <string>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

TriangleGradients triangle_gradients(const Mesh& m) {
  validate_mesh_arrays(m);
  return triangle_gradients(m, m.num_faces() > 0 ? mean_edge_length(m) : 0.0);
}

TriangleGradients triangle_gradients(const Mesh& m, double h) {
  validate_mesh_arrays(m);
  if (!m.is_triangle_mesh())
    for (int32_t f = 0; f < m.num_faces(); ++f)
      if (m.face(f).size() != 3)
        fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has " +
                                      std::to_string(m.face(f).size()) + " vertices; gradients need triangles");
  const double sc = power_of_two_scale(h);
  TriangleGradients g;
  g.nv = m.num_vertices();
  g.nf = m.num_faces();
  const size_t nf = static_cast<size_t>(g.nf);
  g.tri.resize(3 * nf);
  g.area.resize(nf);
  g.basis.resize(9 * nf);
  for (int32_t k = 0; k < g.nf; ++k) {
    cancel_point(k);
    const int32_t v[3] = {m.f0[k], m.f1[k], m.f2[k]};
    for (int s = 0; s < 3; ++s) g.tri[3 * k + s] = v[s];
    double e[3][3];  // e[s] = v_{s+2} - v_{s+1}: the edge opposite corner s
    for (int s = 0; s < 3; ++s) {
      const int32_t a = v[(s + 1) % 3], b = v[(s + 2) % 3];
      e[s][0] = (m.x[b] - m.x[a]) * sc;
      e[s][1] = (m.y[b] - m.y[a]) * sc;
      e[s][2] = (m.z[b] - m.z[a]) * sc;
    }
    // Vector area (twice the area times the unit normal): (v1 - v0) x (v2 - v0).
    // Scaled by sc (power_of_two_scale): exact, and no under/overflow at any mesh scale.
    const double ux = (m.x[v[1]] - m.x[v[0]]) * sc, uy = (m.y[v[1]] - m.y[v[0]]) * sc, uz = (m.z[v[1]] - m.z[v[0]]) * sc;
    const double wx = (m.x[v[2]] - m.x[v[0]]) * sc, wy = (m.y[v[2]] - m.y[v[0]]) * sc, wz = (m.z[v[2]] - m.z[v[0]]) * sc;
    const double ax = uy * wz - uz * wy, ay = uz * wx - ux * wz, az = ux * wy - uy * wx;
    const double twice = std::sqrt(ax * ax + ay * ay + az * az);
    // Same threshold as the mesh report: an area not above 1e-14 h^2 has no usable normal.
    if (!(twice * 0.5 > kDegenerateAreaRelative * (h * sc) * (h * sc)) || !std::isfinite(twice))
      fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(k) + " (vertices " + std::to_string(v[0]) +
                                    ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) +
                                    ") has zero area; its gradient is undefined");
    g.area[k] = 0.5 * twice / (sc * sc);
    const double nx = ax / twice, ny = ay / twice, nz = az / twice;
    const double inv = 1.0 / twice;  // 1 / (2 A_k)
    double* b = g.basis.data() + 9 * static_cast<int64_t>(k);
    for (int s = 0; s < 3; ++s) {
      b[3 * s + 0] = (ny * e[s][2] - nz * e[s][1]) * inv * sc;
      b[3 * s + 1] = (nz * e[s][0] - nx * e[s][2]) * inv * sc;
      b[3 * s + 2] = (nx * e[s][1] - ny * e[s][0]) * inv * sc;
    }
  }
  index_vertex_faces(g);
  return g;
}

void index_vertex_faces(TriangleGradients& g) {
  g.vf_offsets.assign(static_cast<size_t>(g.nv) + 1, 0);
  for (int32_t v : g.tri) ++g.vf_offsets[v + 1];
  for (int32_t i = 0; i < g.nv; ++i) g.vf_offsets[i + 1] += g.vf_offsets[i];
  g.vf_faces.resize(g.tri.size());
  HostVector<int64_t> pos(g.vf_offsets.begin(), g.vf_offsets.end() - 1);
  for (int32_t k = 0; k < g.nf; ++k)
    for (int s = 0; s < 3; ++s) g.vf_faces[pos[g.tri[3 * k + s]]++] = k;
}

}  // namespace locus
