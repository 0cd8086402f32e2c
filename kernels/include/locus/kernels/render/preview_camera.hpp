// Where a preview looks from (a z-up mesh must not render
// on its back). The camera is derived from the surface's principal axes
// (area-weighted covariance of the face centroids, e1 >= e2 >= e3):
//  * "up" on the screen is whichever of e1, e2 is closer to the file's y or
//    z axis (y on a tie), signed to point along +y / +z: a standing figure
//    (height = e1) and a lying animal (height = e2) both stand upright,
//    whether the file is y-up or z-up.
//  * the camera looks along the remaining axis e3 (the widest silhouette),
//    from the side of the "front" convention (-z for y-up files, as the CGAL
//    armadillo faces; +y for z-up files, the same side after turning y-up
//    into z-up);
//  * an open surface whose normals mostly agree (|sum of area vectors| > half
//    the area: a terrain, a disk) is seen like a landscape: its mean normal
//    is "up" and the camera looks from the front convention's side, level;
//  * then turned 30 degrees about "up" and raised 20 degrees (40 for the
//    landscape) for a three-quarter view.
// `view` (--view x,y,z) replaces the looking direction (no turn, no raise):
// the camera sits on the side of the mesh that `view` points to; "up" stays
// as above (or the next principal axis when `view` is parallel to it).
// Deterministic: no random choice; eigenvector signs are fixed by the rules
// above, not by the eigen solver.
#pragma once
#include <array>
#include <optional>

#include "locus/mesh.hpp"

namespace locus {

using Vec3d = std::array<double, 3>;

struct PreviewCamera {
  Vec3d centre{0, 0, 0};  // of the area-weighted surface
  Vec3d right{1, 0, 0}, up{0, 1, 0}, back{0, 0, 1};  // orthonormal; `back` points from the mesh to the camera
  bool one_sided = false;  // open surface seen from the side its normals face
};

PreviewCamera principal_axes_camera(const Mesh& m, const std::optional<Vec3d>& view = std::nullopt);

// Symmetric 3 x 3 eigen-decomposition (cyclic Jacobi): eigenvalues descending,
// vectors[k] the unit eigenvector of values[k].
struct SymmetricEigen3 {
  Vec3d values;
  std::array<Vec3d, 3> vectors;
};
SymmetricEigen3 symmetric_eigen3(const std::array<Vec3d, 3>& a);

}  // namespace locus
