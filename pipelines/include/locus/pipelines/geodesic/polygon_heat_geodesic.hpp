// Heat geodesic distance on polygon meshes (quads, mixed, n-gons), whole mesh
// (thesis §6.4.1, eqs. 6.3-6.6, on polygons; the operators after Bunge et al.
// 2020, "Polygon Laplacian made simple": a virtual vertex per polygon).
//
// Each face with k > 3 corners gets a virtual vertex at the mean of its corners
// and is split into the k triangles of the fan around it; triangles stay as
// they are. P (n_refined x n) maps polygon-vertex values to the refined mesh:
// the identity on the mesh's own vertices, weight 1/k from each corner to a
// virtual one. On the refined mesh the usual operators (cotan Laplacian L_C,
// lumped mass, per-triangle gradients, eq. 6.4) exist, and the polygon ones are
// their Galerkin restrictions:
//     L = P^T L_C P,   M = diag(P^T m),   grad u = grad_refined(P u),   div = P^T div_refined,
// so L is symmetric negative semidefinite with L 1 = 0, and the heat method runs
// on the mesh's own vertices: (M - t L) h = e_source; X = -grad log h / |.| per
// fan triangle; (-L + eps M) d = P^T D X; d shifted to 0 at the source. The
// pattern of L couples all corners of a face (no diagonals are added to the
// mesh; a quad mesh's distance is not biased along one diagonal as a
// triangulation's is). The mean of the corners (not the area-minimizing point
// of Bunge et al.) is exact for planar convex faces up to the fan's shape; on
// strongly non-planar faces it is the first thing to revisit.
//
// t = t_factor h^2 with h the mean length of the polygon edges (not of the fan's
// spokes); eps as HeatGeodesicOptions::poisson_rel. Whole-mesh queries only
// (localized queries and log maps on polygons: docs/logmap.md, "Polygon meshes").
// Needs a closed or bounded manifold polygon mesh without zero-area triangles
// in its fan split; Error(BadInput) otherwise (from the triangle checks).
// Thread safety: const after construction; query_full allocates its own scratch.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/mesh/mesh_gradient.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"

namespace locus {

struct PolygonHeatGeodesicOptions {
  // t = t_factor h^2, h the mean polygon edge. 8, not the triangles' 4: a quad
  // lattice's heat kernel is more anisotropic (4-fold) than a triangle
  // lattice's (6-fold), and h here leaves out the diagonals. Cube-sphere 129
  // (~100k quads), 10 centers, log map E_a / E_d: 5.0e-3 / 9.0e-4 at 4,
  // 2.9e-3 / 6.7e-4 at 8, 1.8e-3 / 6.9e-4 at 16 (docs/logmap.md, "Polygon meshes").
  double t_factor = 8.0;
  double poisson_rel = 1e-5;  // as HeatGeodesicOptions::poisson_rel
};

class PolygonHeatGeodesic {
 public:
  explicit PolygonHeatGeodesic(const Mesh& m, const PolygonHeatGeodesicOptions& opt = {}, const RunContext& ctx = {});
  int32_t num_vertices() const { return n_; }
  double mean_edge_length() const { return h_; }
  double time() const { return t_; }
  // distance has num_vertices() entries; 0 at the source.
  void query_full(int32_t source, std::span<double> distance) const;
  // Building blocks shared with the polygon log map (polygon_logmap.hpp).
  // h = A^{-1} e_source (in place: h holds e_source on entry, n entries).
  void solve_heat(std::span<double> h) const;
  // From the heat at every vertex to distances at every vertex (0 at source).
  void distance_from_heat(std::span<const double> h, int32_t source, std::span<double> distance) const;
  const Mesh& refined() const { return refined_; }           // vertices, then one virtual vertex per face of k > 3
  const TriangleGradients& gradients() const { return grad_; }  // of the refined mesh
  // The polygon face a virtual vertex v >= num_vertices() stands for.
  int32_t face_of_virtual(int32_t v) const { return face_of_virtual_[v - n_]; }
  std::span<const int32_t> face(int32_t f) const {
    return {face_vertices_.data() + face_offsets_[f], static_cast<size_t>(face_offsets_[f + 1] - face_offsets_[f])};
  }

 private:
  int32_t n_ = 0;
  double h_ = 0, t_ = 0;
  Mesh refined_;
  TriangleGradients grad_;
  std::vector<int32_t> face_of_virtual_;  // per virtual vertex (refined ids n.. ): its face
  std::vector<int32_t> face_offsets_, face_vertices_;  // the polygon faces (for P)
  NumericFactor heat_, poisson_;
  // y (refined) = P x (polygon vertices) and x += P^T y.
  void prolong(std::span<const double> x, std::vector<double>& y) const;
  void restrict_add(std::span<const double> y, std::span<double> x) const;
};

}  // namespace locus
