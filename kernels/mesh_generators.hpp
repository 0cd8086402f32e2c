// Procedural meshes for tests and benchmarks, and 1:4 midpoint subdivision.
// All deterministic given their arguments (random ones take an explicit seed).
#pragma once
#include <cstdint>

#include "locus/mesh.hpp"

namespace locus {

// Icosahedron subdivided `level` times (1:4), vertices projected on the sphere of radius r.
Mesh make_icosphere(int level, double radius = 1.0);
// Convex hull of n uniformly random points on the unit sphere (irregular, thin triangles).
Mesh make_random_sphere(int32_t n, uint64_t seed);
// Torus with major radius R, minor radius r, nu x nv quads split into triangles.
Mesh make_torus(int32_t nu, int32_t nv, double R = 1.0, double r = 0.4);
// Regular quad torus (polygon mesh, 4-gons).
Mesh make_quad_torus(int32_t nu, int32_t nv, double R = 1.0, double r = 0.4);
// Planar square grid [0,1]^2 with (n+1)^2 vertices; flip_fraction of interior
// diagonals flipped at random (seeded), keeping triangles valid.
Mesh make_grid(int32_t n, double flip_fraction = 0.0, uint64_t seed = 1);
// Planar unit disk, `rings` concentric rings, roughly equilateral triangles; optional flips.
Mesh make_disk(int32_t rings, double flip_fraction = 0.0, uint64_t seed = 1);
// 1:4 midpoint subdivision of a triangle mesh, `times` times (new vertices at edge midpoints,
// not projected). Original vertices keep their ids; new ones are appended.
Mesh subdivide_midpoint(const Mesh& m, int times);

}  // namespace locus
