// Helpers of the Session tests (tests/engine/session*.cpp); their Eigen
// oracles take locus::test::to_eigen from tests/kernels/matrix_fixtures.hpp.
#pragma once
#include <functional>

#include "locus/error.hpp"

namespace locus::test {

// The code of the locus::Error f throws; 0 when it throws none.
inline ErrorCode code_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.code();
  }
  return static_cast<ErrorCode>(0);
}

}  // namespace locus::test
