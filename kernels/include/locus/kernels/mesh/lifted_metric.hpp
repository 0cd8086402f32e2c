// Operators of a triangle mesh whose vertex positions live in R^d, computed from
// edge lengths alone: the R^6 lift of the anisotropic CVT (thesis §3.7.1), the
// triangle areas in that metric, and the heat operator M - t L_C whose cotan
// weights and lumped masses come from those lengths.
//
// Anisotropic CVT measures distances in R^6: the mesh scaled to a unit bounding box
// (largest side 1) and lifted by (p, lambda n) with area-weighted vertex normals n,
// so that cells also follow normal variation (thesis: lambda = 0.05). A lifted
// triangle is flat in its own plane, so everything the heat method needs of it
// follows from its three edge lengths: the area by Heron's formula in Kahan's
// stable form (exact for needles), and cot at a corner = (a^2 + b^2 - c^2) / 4A.
// In R^3 these are the cotan operator of mesh_operators.hpp up to rounding; that
// one stays the operator of the mesh's own positions (it is scaled to avoid
// overflow and checks degeneracy relative to h), this one serves any dimension.
//
// Positions are interleaved: pos[v * dim + c]. Thread safety: re-entrant.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

// Area of a triangle from its squared edge lengths, by Kahan's stable Heron
// formula; 0 when the lengths violate the triangle inequality.
double triangle_area_from_squared_lengths(double l2a, double l2b, double l2c);

// Triangle areas of a mesh whose positions are given in `dim` dimensions. BadInput
// unless m is a triangle mesh, BadUsage unless pos holds dim values per vertex.
HostVector<double> face_areas_from_positions(const Mesh& m, std::span<const double> pos, int dim);
// The same for the mesh's own R^3 positions.
HostVector<double> face_areas(const Mesh& m);

// Heat operator M - t L_C of a triangle mesh with positions in `dim` dimensions,
// on the lower pattern diagonal + edges; returns the lumped mass (one third of
// the incident areas) and the mean edge length in that metric. Throws BadInput
// naming the face if a triangle has zero area in that metric.
CscMatrix heat_operator_from_positions(const Mesh& m, std::span<const double> pos, int dim, double t,
                                       HostVector<double>& mass, double& mean_edge);

// The R^6 lift (p, lambda n) of the mesh scaled to a unit bounding box (6 per
// vertex). Throws BadInput when the mesh has no extent.
std::vector<double> lifted_positions(const Mesh& m, double lambda);

}  // namespace locus
