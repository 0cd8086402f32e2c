// Defect detection for the choice between the cotan and the robust operator
// (robust_laplacian.hpp): the one-pass report of mesh_topology.hpp gives the
// non-manifold vertices, zero-area faces and unreferenced vertices; here the
// edges it lumps together as non-manifold are told apart (more than two faces vs
// two faces running the edge the same way), and needles are found by their
// angles, as the heat geodesic measures them.
#include "locus/kernels/mesh/mesh_defects.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/error.hpp"

namespace locus {

namespace {

// Smallest and largest angle of triangle (a, b, c), and the vertex of the worse
// one, with the edge vectors scaled by a power of two (no underflow at any scale).
// Returns the vertex whose angle is within kNeedleAngle of 0 or pi, or -1.
int32_t needle_vertex(const Mesh& m, const int32_t v[3]) {
  for (int k = 0; k < 3; ++k) {
    const int32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
    double u[3] = {m.x[b] - m.x[a], m.y[b] - m.y[a], m.z[b] - m.z[a]};
    double w[3] = {m.x[c] - m.x[a], m.y[c] - m.y[a], m.z[c] - m.z[a]};
    const double sc = power_of_two_scale(std::max({std::abs(u[0]), std::abs(u[1]), std::abs(u[2]), std::abs(w[0]),
                                                   std::abs(w[1]), std::abs(w[2])}));
    for (int q = 0; q < 3; ++q) u[q] *= sc, w[q] *= sc;
    const double cx = u[1] * w[2] - u[2] * w[1], cy = u[2] * w[0] - u[0] * w[2], cz = u[0] * w[1] - u[1] * w[0];
    const double angle = std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), u[0] * w[0] + u[1] * w[1] + u[2] * w[2]);
    if (angle < kNeedleAngle || angle > M_PI - kNeedleAngle) return a;
  }
  return -1;
}

struct Needles {
  int64_t count = 0;
  int32_t first_face = -1, first_vertex = -1;
};

}  // namespace

MeshDefects detect_mesh_defects(const Mesh& m) {
  validate_mesh_arrays(m);
  const EdgeIncidence inc = edge_incidence(m);
  return detect_mesh_defects(m, inc, analyze_mesh(m, inc));
}

MeshDefects detect_mesh_defects(const Mesh& m, const EdgeIncidence& inc, const MeshReport& r) {
  if (r.first_non_triangle_face >= 0)
    fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(r.first_non_triangle_face) +
                                  " is not a triangle; defect detection needs a triangle mesh");
  if (r.first_non_finite_vertex >= 0)
    fail(ErrorCode::BadInput, mesh_name(m) + ": vertex " + std::to_string(r.first_non_finite_vertex) +
                                  " has a non-finite coordinate");
  // The report's counts; the edge kinds and needles are counted below.
  MeshDefects d{.non_manifold_vertices = r.non_manifold_vertices, .first_non_manifold_vertex = r.first_non_manifold_vertex,
                .first_non_manifold_vertex_fans = r.first_non_manifold_vertex_fans,
                .zero_area_faces = r.degenerate_faces, .first_zero_area_face = r.first_degenerate_face,
                .unreferenced_vertices = r.unreferenced_vertices, .first_unreferenced_vertex = r.first_unreferenced_vertex};
  const Edges& E = inc.edges;
  const int64_t ne = static_cast<int64_t>(E.e0.size());
  const int32_t* fv = m.face_vertices.data();
  const EdgeCorners corners(inc);
  for (int64_t e = 0; e < ne; ++e) {
    if (E.face_count[e] > 2) {
      if (d.non_manifold_edges++ == 0) {
        d.first_non_manifold_edge_v0 = E.e0[e];
        d.first_non_manifold_edge_v1 = E.e1[e];
        d.first_non_manifold_edge_faces = E.face_count[e];
      }
    } else if (E.face_count[e] == 2) {
      const int64_t p = corners.offsets()[e];
      // Both half-edges leave the same end: the faces run the edge the same way.
      if (fv[corners.corners()[p]] == fv[corners.corners()[p + 1]] && d.inconsistent_orientation_edges++ == 0) {
        d.first_inconsistent_edge_v0 = E.e0[e];
        d.first_inconsistent_edge_v1 = E.e1[e];
      }
    }
  }
  // Needles: faces with an extreme angle that are not already zero-area (the
  // report's threshold, recomputed per face from the same scale).
  const double h = r.mean_edge_length;
  const double sc = power_of_two_scale(h);
  const double min_double_area = 2.0 * kDegenerateAreaRelative * (h * sc) * (h * sc);
  // In parallel (three angles per face: ~0.3 s at 832k faces), reduced to the
  // count and the lowest face, so the answer does not depend on the threads.
  const Needles n = tbb::parallel_reduce(
      tbb::blocked_range<int32_t>(0, m.num_faces()), Needles{},
      [&](const tbb::blocked_range<int32_t>& range, Needles acc) {
        for (int32_t f = range.begin(); f < range.end(); ++f) {
          const int32_t v[3] = {fv[3 * f], fv[3 * f + 1], fv[3 * f + 2]};
          if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
          const double ux = (m.x[v[1]] - m.x[v[0]]) * sc, uy = (m.y[v[1]] - m.y[v[0]]) * sc,
                       uz = (m.z[v[1]] - m.z[v[0]]) * sc;
          const double wx = (m.x[v[2]] - m.x[v[0]]) * sc, wy = (m.y[v[2]] - m.y[v[0]]) * sc,
                       wz = (m.z[v[2]] - m.z[v[0]]) * sc;
          const double cx = uy * wz - uz * wy, cy = uz * wx - ux * wz, cz = ux * wy - uy * wx;
          if (!(std::sqrt(cx * cx + cy * cy + cz * cz) > min_double_area)) continue;
          const int32_t a = needle_vertex(m, v);
          if (a < 0) continue;
          if (acc.count++ == 0 || f < acc.first_face) acc.first_face = f, acc.first_vertex = a;
        }
        return acc;
      },
      [](Needles a, const Needles& b) {
        if (b.count > 0 && (a.count == 0 || b.first_face < a.first_face))
          a.first_face = b.first_face, a.first_vertex = b.first_vertex;
        a.count += b.count;
        return a;
      });
  d.needle_faces = n.count;
  if (n.count > 0) d.first_needle_face = n.first_face, d.first_needle_vertex = n.first_vertex;
  return d;
}

}  // namespace locus
