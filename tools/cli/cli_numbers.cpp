// Numeric helpers of the tools (cli_numbers.hpp).
#include "tools/cli/cli_numbers.hpp"

#include <algorithm>

#include "locus/error.hpp"

namespace locus::cli {

double median(std::vector<double> v) {
  if (v.empty()) fail(ErrorCode::Internal, "median of an empty sample");
  std::sort(v.begin(), v.end());
  const size_t k = v.size() / 2;
  return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
}

}  // namespace locus::cli
