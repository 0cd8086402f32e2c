// Private random numbers for METIS (kernels/include/locus/kernels/order/metis_random.hpp).
#include "locus/kernels/order/metis_random.hpp"

namespace {

thread_local locus::MetisRandomScope* t_scope = nullptr;
// Only for a METIS call outside any scope (locus makes none): still never the C library's generator.
thread_local uint64_t t_unscoped_state = 1;

// splitmix64: small state, good statistics, cheap to seed. The orderings, and
// so every factor, depend on this sequence: changing it changes results.
uint64_t next(uint64_t& s) {
  uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

// The names METIS' rand()/srand() were renamed to (cmake/metis.cmake); hidden,
// like METIS itself, so no other library in the process can bind to them.
extern "C" __attribute__((visibility("hidden"))) int locus_metis_rand(void) noexcept {
  if (locus::MetisRandomScope* s = t_scope) {
    ++s->draws_;
    return static_cast<int>(next(s->state_) >> 33);  // 31 bits: [0, RAND_MAX]
  }
  return static_cast<int>(next(t_unscoped_state) >> 33);
}

extern "C" __attribute__((visibility("hidden"))) void locus_metis_srand(unsigned seed) noexcept {
  if (locus::MetisRandomScope* s = t_scope)
    s->state_ = seed;
  else
    t_unscoped_state = seed;
}

namespace locus {

MetisRandomScope::MetisRandomScope() : outer_(t_scope) { t_scope = this; }
MetisRandomScope::~MetisRandomScope() { t_scope = outer_; }

}  // namespace locus
