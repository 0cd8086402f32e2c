// Welding by exact position for asset files (io/include/locus/io/weld_vertices.hpp).
//
// Why exact equality and not a tolerance: an exporter splits a vertex at a UV
// or normal seam by writing the same position twice, so the copies are
// bit-identical after the same node transform, and exact equality welds every
// seam while never merging two points the artist kept apart (thin walls,
// shells that touch, the two lips of a cut). A tolerance would merge those,
// and tolerance welding is not transitive (a chain of close points merges
// points farther apart than the tolerance) unless snapped to a grid, which
// then splits close pairs across cell borders. Parts placed by different node
// transforms that only meet up to rounding stay separate, as in the file.
//
// A sort of the vertex ids by (x, y, z, id) groups equal positions; O(n log n),
// no hashing, deterministic for any input order.
#include "locus/io/weld_vertices.hpp"

#include <algorithm>
#include <numeric>

namespace locus::io {

int32_t weld_by_position(std::span<const double> x, std::span<const double> y, std::span<const double> z,
                         std::vector<int32_t>& map) {
  const size_t n = x.size();
  // Adding 0.0 turns -0.0 into +0.0, so both compare equal under < as well.
  auto key = [&](int32_t i, int c) {
    const double v = c == 0 ? x[size_t(i)] : c == 1 ? y[size_t(i)] : z[size_t(i)];
    return v + 0.0;
  };
  std::vector<int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int32_t a, int32_t b) {
    for (int c = 0; c < 3; ++c) {
      const double ka = key(a, c), kb = key(b, c);
      if (ka != kb) return ka < kb;
    }
    return a < b;
  });
  // first[i]: the smallest id with i's position (the head of its sorted run).
  std::vector<int32_t> first(n);
  for (size_t k = 0; k < n; ++k) {
    const int32_t i = order[k];
    const bool same = k > 0 && key(order[k - 1], 0) == key(i, 0) && key(order[k - 1], 1) == key(i, 1) &&
                      key(order[k - 1], 2) == key(i, 2);
    first[size_t(i)] = same ? first[size_t(order[k - 1])] : i;
  }
  map.assign(n, -1);
  int32_t next = 0;
  for (size_t i = 0; i < n; ++i) map[i] = first[i] == int32_t(i) ? next++ : map[size_t(first[i])];
  return next;
}

}  // namespace locus::io
