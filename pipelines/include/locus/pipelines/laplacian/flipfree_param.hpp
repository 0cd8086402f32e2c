// Flip-free parameterization of a disk-like polygon mesh (thesis §2.6,
// "Parameterization"; eq. 2.4 with the boundary on a circle).
//
// The boundary loop goes to the unit circle, spaced by 3-D arc length, in the
// direction of the loop (counter-clockwise faces stay counter-clockwise). The
// interior solves eq. 2.4 with one of three Laplacians on the polygon edges:
//  * perfect: the weights of the planar Algorithm 1 run on the mapped mesh, i.e.
//    with that fixed circle boundary and the 3-D edge lengths as targets
//    (pipelines/perfect_laplacian). All weights are >= 0, so by Tutte/Floater the
//    map is an embedding with convex faces: no flipped face, for triangles and
//    polygons alike;
//  * cotan: the cotan weights of the surface (triangle meshes only); they can be
//    negative and then faces may flip;
//  * uniform: ω = 1 (Tutte's barycentric map; flip-free but geometry-blind).
// The result is checked face by face: a face is flipped when any of its corners
// turns clockwise (for a polygon that also catches reflex corners, i.e. non-convex
// faces), degenerate when its area or one of its edges (nearly) vanishes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"

namespace locus {

enum class ParamMethod { Perfect, Cotan, Uniform };

struct FlipFreeParamOptions {
  ParamMethod method = ParamMethod::Perfect;
  PerfectLaplacianOptions iteration;  // for ParamMethod::Perfect
};

// "perfect" | "cotan" | "uniform"; throws BadUsage otherwise.
ParamMethod parse_param_method(const std::string& name);
const char* param_method_name(ParamMethod m);

// Face orientation in the plane (counter-clockwise expected).
struct PlanarFaceCheck {
  int64_t flipped_faces = 0;      // a corner turning clockwise (or negative area)
  int64_t degenerate_faces = 0;   // not flipped, but area or an edge ~ 0 (relative 1e-14)
  int64_t first_flipped = -1, first_degenerate = -1;
  double min_corner_sin = 1;      // smallest sin of a corner's turn over all faces
};
PlanarFaceCheck check_planar_faces(const Mesh& m, const std::vector<double>& u, const std::vector<double>& v);

struct FlipFreeParamResult {
  std::vector<double> uv;        // 2 * nv, interleaved (u, v), for WriteOptions.uv
  PlanarFaceCheck faces;
  int64_t negative_weights = 0;  // cotan: edges with a negative weight
  double min_weight = 0;         // of the weights used (normalized for perfect)
  // Algorithm 1 (perfect only):
  bool converged = true;
  int iterations = 0;
  int64_t zero_weights = 0;
  double first_iter_s = 0, iter_s = 0;
  double total_s = 0;
};

// Needs a connected manifold mesh with exactly one boundary loop (BadInput naming
// what is wrong otherwise), and triangles for the cotan method.
FlipFreeParamResult flipfree_param(const Mesh& m, const FlipFreeParamOptions& opt = {}, const RunContext& ctx = {});

}  // namespace locus
