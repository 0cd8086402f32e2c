// A clean manifold patch on which the cotan heat method fails: CGAL's sample
// fold.off (12 vertices, 12 faces; its coordinates as that file gives them).
// Its thin, obtuse triangles make the cotan heat method's distance from vertex 0
// negative at vertex 9 (t = 4 h^2); the robust operator's intrinsic Delaunay
// triangles answer. Used by the engine's and the CLI's operator tests.
#pragma once
#include "locus/mesh.hpp"

namespace locus::test {

inline Mesh fold_mesh() {
  const double xyz[12][3] = {
      {43.15737184731, 34.84024238294, 10.83859524351},
      {42.98540000001, 34.82749999966, 10.832000732},
      {42.929, 34.7583999997, 10.847301483},
      {42.88549999997, 34.70430000033, 10.852298737},
      {43.04129102826, 34.78502447089, 10.83723942966},
      {42.86200000002, 34.64070000034, 10.860298157},
      {42.97115235895, 34.71510881864, 10.84738285826},
      {43.0488134204, 34.48220500395, 10.81679581296},
      {42.95510000002, 34.57909999974, 10.841098785},
      {43.25889785981, 34.80894544183, 10.83314126353},
      {43.01115727956, 34.69207987471, 10.83639245934},
      {43.0896664833, 34.62410991971, 10.8179299228},
  };
  const int32_t tri[12][3] = {{4, 1, 6}, {6, 2, 3}, {5, 8, 6}, {10, 4, 6}, {11, 10, 7}, {10, 0, 4},
                              {6, 8, 7}, {10, 6, 7}, {10, 11, 9}, {3, 5, 6}, {2, 6, 1}, {9, 0, 10}};
  Mesh m;
  for (const auto& p : xyz) m.add_vertex(p[0], p[1], p[2]);
  for (const auto& t : tri) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

}  // namespace locus::test
