// Private random numbers for METIS calls.
//
// METIS draws its random numbers through rand()/srand(). locus compiles METIS
// itself (cmake/metis.cmake) with those two names replaced by
// locus_metis_rand()/locus_metis_srand(), defined next to this header: the C
// library's rand(), which the host program may use, is never called or
// redefined. Inside a MetisRandomScope the draws come from a generator owned by
// the scope, so two METIS calls at once (the halves of a nested dissection,
// two Sessions) never share a sequence; METIS seeds it with srand at the start
// of every call, so each call is reproducible on its own.
#pragma once
#include <cstdint>

#include "locus/core/non_copyable.hpp"

namespace locus {

// While alive, METIS calls on this thread draw from this scope's generator.
class MetisRandomScope : NonCopyable {
 public:
  MetisRandomScope();
  ~MetisRandomScope();
  uint64_t draws() const { return draws_; }  // numbers METIS took from this scope

  uint64_t state_ = 0;
  uint64_t draws_ = 0;

 private:
  MetisRandomScope* outer_ = nullptr;
};

}  // namespace locus
