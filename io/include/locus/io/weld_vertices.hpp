// Welding by position (io/src/weld_vertices.cpp): the vertices an exporter
// split at UV or normal seams merged back into one. Internal to io/.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace locus::io {

// map[i] = the welded vertex of vertex i, for positions (x[i], y[i], z[i])
// (finite). Vertices weld when their positions are exactly equal (-0 equals
// +0); welded vertices are numbered in the order of their first vertex, so
// the result depends only on the input order (deterministic). Returns the
// number of welded vertices.
int32_t weld_by_position(std::span<const double> x, std::span<const double> y, std::span<const double> z,
                         std::vector<int32_t>& map);

}  // namespace locus::io
