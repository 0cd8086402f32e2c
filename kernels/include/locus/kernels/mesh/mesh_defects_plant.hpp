// Planted mesh defects, for the tests and the accuracy figure of the robust
// Laplacian (robust_laplacian.hpp): each kind the defect detection
// (mesh_defects.hpp) reports, put into a clean triangle mesh at `count` sites
// without changing the surface it describes (except for the fin, which adds a
// flap). The original vertices keep their ids and positions; new ones are appended.
#pragma once
#include <cstdint>

#include "locus/mesh.hpp"

namespace locus {

enum class PlantedDefect {
  Fin,            // a triangle on an existing edge, apex h off the surface: a non-manifold edge
  Bowtie,         // two non-adjacent faces of a vertex's fan removed: two fans meet at it
  ZeroArea,       // a face split at an edge midpoint on one side only, the crack closed by a flat triangle
  Needle,         // an edge split at 1e-6 of its length on both sides: four triangles, two of them needles
  FlippedPatch,   // the faces of a vertex's fan reversed: inconsistent orientation on the fan's rim
  Unreferenced,   // a vertex in no face
  DuplicateFace,  // a face given twice
};

inline constexpr int kNumPlantedDefects = 7;
const char* planted_defect_name(PlantedDefect kind);

// Sites: vertices spread over the id range from the top down (vertex 0, a usual
// heat source, is the last one picked), each touched once. Needs a closed
// manifold triangle mesh with vertices of degree >= 5 for Bowtie (icospheres).
Mesh plant_mesh_defect(const Mesh& clean, PlantedDefect kind, int32_t count);

}  // namespace locus
