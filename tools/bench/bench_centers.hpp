// The query centers of the log-map benchmarks: seeded random vertices, or on an
// analytic surface the centers an accuracy run names.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "tools/bench/analytic_surfaces.hpp"

namespace locus::bench {

// Distinct seeded centers (splitmix64 through cli::random_vector).
std::vector<int32_t> pick_centers(int32_t n, int q, uint64_t seed);

// The centers: center_ids (comma-separated), else the bump's top, else `count`
// random ones (or, with center_set "irregular", `count` vertices of valence
// != 6 spread evenly over the ids: on icospheres the icosahedron's 12 corners,
// valence 5). BadUsage for a bad id or set name.
std::vector<int32_t> accuracy_centers(const Surface& s, const std::string& center_ids, const std::string& center_set,
                                      int count, uint64_t seed);

}  // namespace locus::bench
