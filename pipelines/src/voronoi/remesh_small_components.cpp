// One-triangle components of a remesh set to their input triangle
// (pipelines/include/locus/pipelines/voronoi/remesh_small_components.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_small_components.hpp"

#include <array>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

namespace {

// Faces per component of a triangle mesh (connected_components: by shared vertices), and each face's component.
struct FaceComponents {
  std::vector<int32_t> of_face, faces;
};

FaceComponents face_components(const Mesh& m) {
  std::vector<int32_t> of_vertex;
  FaceComponents c;
  c.faces.assign(static_cast<size_t>(connected_components(m, of_vertex)), 0);
  c.of_face.resize(static_cast<size_t>(m.num_faces()));
  for (int32_t f = 0; f < m.num_faces(); ++f) ++c.faces[c.of_face[f] = of_vertex[m.f0[f]]];
  return c;
}

}  // namespace

int32_t restore_single_triangles(const Mesh& input, const TriangleGrid& grid, Mesh& remesh) {
  const FaceComponents rc = face_components(remesh);
  FaceComponents ic;
  int32_t restored = 0;
  for (int32_t f = 0; f < remesh.num_faces(); ++f) {
    if (rc.faces[rc.of_face[f]] != 1) continue;
    if (ic.of_face.empty()) ic = face_components(input);
    const std::array<int32_t, 3> v = {remesh.f0[f], remesh.f1[f], remesh.f2[f]};
    std::array<double, 3> c{0, 0, 0};
    for (int32_t x : v) c = {c[0] + remesh.x[x] / 3, c[1] + remesh.y[x] / 3, c[2] + remesh.z[x] / 3};
    const ClosestPoint cp = grid.closest(c);
    if (cp.face < 0 || ic.faces[ic.of_face[cp.face]] != 1) continue;
    // The input's corners in the input's order, starting at the corner nearest
    // the remesh triangle's first vertex (the orientations agree: the dual
    // keeps the input's).
    const std::array<int32_t, 3> w = {input.f0[cp.face], input.f1[cp.face], input.f2[cp.face]};
    int start = 0;
    double best = -1;
    for (int k = 0; k < 3; ++k) {
      const double dx = input.x[w[k]] - remesh.x[v[0]], dy = input.y[w[k]] - remesh.y[v[0]],
                   dz = input.z[w[k]] - remesh.z[v[0]];
      const double d = dx * dx + dy * dy + dz * dz;
      if (best < 0 || d < best) best = d, start = k;
    }
    for (int k = 0; k < 3; ++k) {
      const int32_t s = w[(start + k) % 3];
      remesh.x[v[k]] = input.x[s], remesh.y[v[k]] = input.y[s], remesh.z[v[k]] = input.z[s];
    }
    ++restored;
  }
  return restored;
}

}  // namespace locus
