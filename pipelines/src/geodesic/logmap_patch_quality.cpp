// Quality of a log map over its patch (pipelines/include/locus/pipelines/geodesic/logmap.hpp;
// beside the accuracy of thesis §6.7): the triangles whose (u, v) image is
// flipped, and the injectivity radius within which none is (decals and
// textures need a one-to-one map).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include "locus/error.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"

namespace locus {

namespace {

void check_patch_ids(const char* what, const TriangleGradients& g, std::span<const int32_t> patch) {
  for (int32_t i : patch)
    if (i < 0 || i >= g.nv) fail(ErrorCode::BadUsage, std::string(what) + ": vertex " + std::to_string(i) + " out of range");
}

// Calls visit(a, b, c, signed area of the image) once per triangle with all
// three corners in the patch (a, b, c: their patch indices, in the face's
// order). `local`: scratch of g.nv entries, all -1 between calls.
template <class Visit>
void visit_patch_triangles(const TriangleGradients& g, std::span<const int32_t> patch, std::span<const double> u,
                           std::span<const double> v, std::vector<int32_t>& local, Visit visit) {
  for (size_t p = 0; p < patch.size(); ++p) local[patch[p]] = static_cast<int32_t>(p);
  for (size_t p = 0; p < patch.size(); ++p) {
    const int32_t i = patch[p];
    for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
      const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(g.vf_faces[q]);
      // Each face once: at its lowest-numbered corner.
      if (i != std::min({t[0], t[1], t[2]})) continue;
      const int32_t a = local[t[0]], b = local[t[1]], c = local[t[2]];
      if (a < 0 || b < 0 || c < 0) continue;
      visit(a, b, c, (u[b] - u[a]) * (v[c] - v[a]) - (u[c] - u[a]) * (v[b] - v[a]));
    }
  }
  for (int32_t i : patch) local[i] = -1;
}

}  // namespace

int64_t count_flipped_triangles(const TriangleGradients& g, std::span<const int32_t> patch,
                                std::span<const double> u, std::span<const double> v, std::vector<int32_t>& local) {
  if (local.size() != static_cast<size_t>(g.nv)) local.assign(g.nv, -1);
  if (u.size() != patch.size() || v.size() != patch.size())
    fail(ErrorCode::BadUsage, "count_flipped_triangles: u and v need one entry per patch vertex");
  check_patch_ids("count_flipped_triangles", g, patch);
  int64_t flipped = 0;
  visit_patch_triangles(g, patch, u, v, local, [&](int32_t, int32_t, int32_t, double area) {
    if (area < 0) ++flipped;
  });
  return flipped;
}

double injectivity_radius(const TriangleGradients& g, std::span<const int32_t> patch, std::span<const double> u,
                          std::span<const double> v, std::span<const double> distance, std::vector<int32_t>& local) {
  if (local.size() != static_cast<size_t>(g.nv)) local.assign(g.nv, -1);
  if (u.size() != patch.size() || v.size() != patch.size() || distance.size() != patch.size())
    fail(ErrorCode::BadUsage, "injectivity_radius: u, v and distance need one entry per patch vertex");
  check_patch_ids("injectivity_radius", g, patch);
  double radius = std::numeric_limits<double>::infinity();
  visit_patch_triangles(g, patch, u, v, local, [&](int32_t a, int32_t b, int32_t c, double area) {
    // A flipped face lies inside every disk that holds its farthest corner.
    if (area < 0) radius = std::min(radius, std::max({distance[a], distance[b], distance[c]}));
  });
  return radius;
}

}  // namespace locus
