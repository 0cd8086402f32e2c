// Private random numbers for METIS (kernels/include/locus/kernels/order/metis_random.hpp).
#include "locus/kernels/order/metis_random.hpp"

#include <dlfcn.h>
#include <metis.h>

#include <mutex>
#include <vector>

namespace {

thread_local locus::MetisRandomScope* t_scope = nullptr;

// splitmix64: small state, good statistics, cheap to seed.
uint64_t next(uint64_t& s) {
  uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

using RandFn = int (*)();
using SrandFn = void (*)(unsigned);

// The C library's functions, found past ours in the lookup order.
RandFn libc_rand() {
  static const RandFn f = reinterpret_cast<RandFn>(dlsym(RTLD_NEXT, "rand"));
  return f;
}
SrandFn libc_srand() {
  static const SrandFn f = reinterpret_cast<SrandFn>(dlsym(RTLD_NEXT, "srand"));
  return f;
}

// Only for a fully static program where dlsym finds no C library rand().
std::mutex g_fallback_mutex;
uint64_t g_fallback_state = 1;

}  // namespace

extern "C" int rand() noexcept {
  if (locus::MetisRandomScope* s = t_scope) {
    ++s->draws_;
    return static_cast<int>(next(s->state_) >> 33);  // 31 bits: [0, RAND_MAX]
  }
  if (const RandFn f = libc_rand()) return f();
  std::lock_guard<std::mutex> lk(g_fallback_mutex);
  return static_cast<int>(next(g_fallback_state) >> 33);
}

extern "C" void srand(unsigned seed) noexcept {
  if (locus::MetisRandomScope* s = t_scope) {
    s->state_ = seed;
    return;
  }
  if (const SrandFn f = libc_srand()) return f(seed);
  std::lock_guard<std::mutex> lk(g_fallback_mutex);
  g_fallback_state = seed;
}

namespace locus {

MetisRandomScope::MetisRandomScope() : outer_(t_scope) { t_scope = this; }
MetisRandomScope::~MetisRandomScope() { t_scope = outer_; }

// Never destroyed: an abandoned METIS call (cancelled ordering) may still hold it at exit.
std::mutex& metis_serial_mutex() {
  static std::mutex* m = new std::mutex;
  return *m;
}

bool metis_random_is_private() {
  static const bool is_private = [] {
    std::lock_guard<std::mutex> serial(metis_serial_mutex());  // the probe may draw from the shared generator
    // A 16x16 grid: METIS' vertex separator uses random matchings, so it draws.
    constexpr idx_t side = 16;
    idx_t n = side * side;
    std::vector<idx_t> xadj(static_cast<size_t>(n) + 1, 0), adj;
    for (idx_t i = 0; i < side; ++i)
      for (idx_t j = 0; j < side; ++j) {
        const idx_t v = i * side + j;
        if (i > 0) adj.push_back(v - side);
        if (i + 1 < side) adj.push_back(v + side);
        if (j > 0) adj.push_back(v - 1);
        if (j + 1 < side) adj.push_back(v + 1);
        xadj[v + 1] = static_cast<idx_t>(adj.size());
      }
    std::vector<idx_t> part(static_cast<size_t>(n));
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_NUMBERING] = 0;
    idx_t sepsize = 0;
    MetisRandomScope scope;
    const int rc = METIS_ComputeVertexSeparator(&n, xadj.data(), adj.data(), nullptr, options, &sepsize, part.data());
    return rc == METIS_OK && scope.draws() > 0;
  }();
  return is_private;
}

}  // namespace locus
