// A sizing density for the remesh's Lloyd sites (thesis §3.7.1, the
// density-weighted CVT of cvt_lloyd.hpp): more sites where the surface bends
// within a remesh edge (small holes, thin tubes), fewer on flat faces. Per
// vertex, the curvature across its edges (the dihedral angle over the mean
// height of the two triangles, which on a cylinder of radius r tessellated
// with needles along its axis is 1/r), spread over one ring; the size wanted
// there is e / (1 + gain * min(e * curvature, cap)) for the remesh edge e, and
// the density (e / size)^4 (a CVT's cell diameter goes as density^(-1/4)).
#pragma once
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

// One value per vertex of `m` (a triangle mesh), each in [1, (1 + gain cap)^4];
// all 1 when gain is 0. `edge`: the remesh's mean edge length (> 0).
std::vector<double> sizing_density(const Mesh& m, double edge, double gain, double cap = 3);

}  // namespace locus
