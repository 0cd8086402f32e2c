// Log map by heat diffusion on polygon meshes (thesis §6.5-6.6, eqs. 6.1, 6.2,
// 6.7, 6.8, on the virtual-vertex polygon operators of polygon_heat_geodesic.hpp).
//
// The triangle log map (logmap.hpp) with full solves, carried over: sources S =
// the center i and every corner of its faces (its polygon neighbors); the heat
// from each, h_k = A^{-1} e_k with A = M - tL the polygon heat operator
// (symmetric, so (h_k)_j = (h_j)_k: these |S| solves give the heat from every
// vertex j at i's star); the direction to j is the area-weighted average, over
// the fan triangles around i, of the gradient of P log h_j (P: the virtual
// vertices take the mean of their face's corners, as for the distance); its
// angle to a reference direction in i's tangent plane is the angular
// coordinate, the polygon heat distance the radial one. The estimator is the
// log one-ring estimator (LogMapAngle::LogHeat) without the lattice
// corrections (they describe triangle lattices); a vertex whose heat from some
// source is not positive falls back to the average of grad P h.
// Tangent frame: normal = the normalized sum of the fan triangles' area
// normals around i; e1 = the projection of the edge to i's lowest-numbered
// polygon neighbor; e2 = n x e1. Whole-mesh solves only (no localized query).
// Thread safety: const after construction; queries allocate their scratch.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/pipelines/geodesic/logmap.hpp"
#include "locus/pipelines/geodesic/polygon_heat_geodesic.hpp"

namespace locus {

class PolygonLogMap {
 public:
  explicit PolygonLogMap(const Mesh& m, const PolygonHeatGeodesicOptions& opt = {}, const RunContext& ctx = {});
  const PolygonHeatGeodesic& geodesic() const { return geo_; }
  // `center` in `patch`; patch ids distinct and in range; out spans one entry per patch vertex.
  void query_full(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out) const;

 private:
  PolygonHeatGeodesic geo_;
  int32_t n_ = 0;
  std::vector<int32_t> vf_offsets_, vf_faces_;  // polygon faces per vertex (CSR)
};

// Polygons with all corners in the patch whose (u, v) image, fanned around its
// first corner, has a triangle of negative signed area (counted once per face).
int64_t count_flipped_polygons(const Mesh& m, std::span<const int32_t> patch, std::span<const double> u,
                               std::span<const double> v);

}  // namespace locus
