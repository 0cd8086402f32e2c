// The query centers of the log-map benchmarks (bench_centers.hpp).
#include "tools/bench/bench_centers.hpp"

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "locus/error.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::bench {

std::vector<int32_t> pick_centers(int32_t n, int q, uint64_t seed) {
  const std::vector<double> r = cli::random_vector(static_cast<size_t>(q) * 4, seed);
  std::vector<int32_t> c;
  for (double x : r) {
    const int32_t v = std::min(n - 1, static_cast<int32_t>((x + 1.0) * 0.5 * n));
    if (std::find(c.begin(), c.end(), v) == c.end()) c.push_back(v);
    if (static_cast<int>(c.size()) == q) break;
  }
  return c;
}

std::vector<int32_t> accuracy_centers(const Surface& s, const std::string& center_ids, const std::string& center_set,
                                      int count, uint64_t seed) {
  const int32_t n = s.mesh.num_vertices();
  std::vector<int32_t> centers;
  if (!center_ids.empty()) {
    std::stringstream ss(center_ids);
    std::string item;
    while (std::getline(ss, item, ',')) {
      char* end = nullptr;
      const long v = std::strtol(item.c_str(), &end, 10);
      if (end == item.c_str() || *end != '\0' || v < 0 || v >= n)
        fail(ErrorCode::BadUsage, "--center-ids: '" + item + "' is not a vertex id (0.." + std::to_string(n - 1) + ")");
      centers.push_back(static_cast<int32_t>(v));
    }
    return centers;
  }
  if (s.kind == "bump") return {0};
  if (center_set == "random") return pick_centers(n, count, seed);
  if (center_set != "irregular") fail(ErrorCode::BadUsage, "--center-set must be random or irregular");
  std::vector<int32_t> valence(static_cast<size_t>(n), 0), odd;
  for (int32_t f = 0; f < s.mesh.num_faces(); ++f) ++valence[s.mesh.f0[f]], ++valence[s.mesh.f1[f]], ++valence[s.mesh.f2[f]];
  for (int32_t v = 0; v < n; ++v)
    if (valence[v] != 6) odd.push_back(v);
  const size_t want = std::min(odd.size(), static_cast<size_t>(std::max(count, 1)));
  for (size_t k = 0; k < want; ++k) centers.push_back(odd[k * odd.size() / want]);
  if (centers.empty()) fail(ErrorCode::BadUsage, "--center-set irregular: every vertex has valence 6");
  return centers;
}

}  // namespace locus::bench
