// Procedural meshes for tests and benchmarks, and 1:4 midpoint subdivision.
// All deterministic given their arguments (random ones take an explicit seed).
#pragma once
#include <cstdint>

#include "locus/mesh.hpp"

namespace locus {

// Icosahedron subdivided `level` times (1:4), vertices projected on the sphere of radius r.
Mesh make_icosphere(int level, double radius = 1.0);
// Convex hull of n uniformly random points on the unit sphere (irregular, thin triangles).
// Closed genus-0 manifold, outward, no degenerate faces. Coordinates lie on a 2^-52 grid
// (|p| = 1 within 2e-16) and the hull is exact on them (kernels/include/locus/kernels/mesh/convex_hull.hpp); a
// sample closer than ~1e-8 to another may fall inside the hull and is then dropped, so
// num_vertices() == n except with a probability of order n^2 * 1e-16. 4 <= n <= 2^26.
Mesh make_random_sphere(int32_t n, uint64_t seed);
// Torus with major radius R, minor radius r, nu x nv quads split into triangles.
Mesh make_torus(int32_t nu, int32_t nv, double R = 1.0, double r = 0.4);
// Regular quad torus (polygon mesh, 4-gons).
Mesh make_quad_torus(int32_t nu, int32_t nv, double R = 1.0, double r = 0.4);
// Planar square grid [0,1]^2 with (n+1)^2 vertices (id = j*(n+1) + i at (i/n, j/n));
// each square is split by its (i,j)-(i+1,j+1) diagonal, or, with probability
// flip_fraction (seeded), by the other one; both keep the triangles positive.
Mesh make_grid(int32_t n, double flip_fraction = 0.0, uint64_t seed = 1);
// Planar unit disk, `rings` concentric rings, roughly equilateral triangles (z = 0):
// the center, then ring k with 6k vertices at radius k/rings; 1 + 3 rings (rings+1)
// vertices, 6 rings^2 faces. With flip_fraction > 0, interior edges are visited in a
// seeded random order and each is flipped with that probability, unless one of its
// triangles was already changed or a new triangle would not be positively oriented.
Mesh make_disk(int32_t rings, double flip_fraction = 0.0, uint64_t seed = 1);
// Cube-sphere: each face of the cube [-1,1]^3 split into n x n quads, vertices
// projected on the unit sphere (polygon mesh, 4-gons, outward; 6 n^2 faces,
// 6 n^2 + 2 vertices). With triangulate, each quad is split by its first diagonal.
Mesh make_cube_sphere(int32_t n, bool triangulate = false);
// 1:4 midpoint subdivision of a triangle mesh, `times` times (new vertices at edge midpoints,
// not projected). Original vertices keep their ids; new ones are appended.
Mesh subdivide_midpoint(const Mesh& m, int times);

}  // namespace locus
