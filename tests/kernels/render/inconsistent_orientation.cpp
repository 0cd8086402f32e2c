// A preview of a mesh whose faces disagree in orientation (kernels/src/render/
// rasterize.cpp draws it as its manifold sheets). Oracle: the same sphere with
// every face consistently oriented, whose picture must come out byte for byte
// the same (drawn without the sheets, the flipped patches' rims differ: their
// vertex normals cancel).
#include <doctest/doctest.h>

#include <vector>

#include "locus/kernels/mesh/mesh_defects_plant.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/render/rasterize.hpp"

using namespace locus;

TEST_CASE("preview: a flipped patch is drawn like the consistently oriented mesh") {
  const Mesh clean = make_icosphere(3);
  // Flipped patches around 8 vertices: faces reversed, the vertices unchanged.
  const Mesh flipped = plant_mesh_defect(clean, PlantedDefect::FlippedPatch, 8);
  REQUIRE(flipped.num_vertices() == clean.num_vertices());
  REQUIRE(flipped.num_faces() == clean.num_faces());
  std::vector<double> z(clean.z.begin(), clean.z.end());
  RasterOptions ro;
  ro.coloring = Coloring::Scalar;
  const RasterImage a = rasterize_mesh(clean, z, ro);
  const RasterImage b = rasterize_mesh(flipped, z, ro);
  CHECK(a.rgb == b.rgb);
}
