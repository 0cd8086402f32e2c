// What METIS' malloc/calloc/realloc/free and its messages were renamed to
// (cmake/metis.cmake; kernels/include/locus/kernels/order/metis_call.hpp).
#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/metis_call.hpp"

namespace {
thread_local locus::MetisCallScope* t_scope = nullptr;
}  // namespace

namespace locus {

MetisCallScope::MetisCallScope(ProgressTicker* ticker) : ticker_(ticker), outer_(t_scope) { t_scope = this; }
MetisCallScope::~MetisCallScope() { t_scope = outer_; }

bool MetisCallScope::should_stop() noexcept {
  if (stopped_) return true;
  if (ticker_) {
    try {
      ticker_->tick();
    } catch (...) {  // a C++ progress callback that throws: stop (nothing may unwind through METIS)
      stopped_ = true;
      return true;
    }
    if (ticker_->context().cancelled()) stopped_ = true;
  }
  return stopped_;
}

}  // namespace locus

extern "C" {

__attribute__((visibility("hidden"))) void* locus_metis_malloc(size_t n) {
  if (locus::MetisCallScope* s = t_scope)
    if (s->should_stop()) return nullptr;
  return locus::host_allocate_nothrow(n);
}

__attribute__((visibility("hidden"))) void* locus_metis_calloc(size_t count, size_t size) {
  if (size != 0 && count > static_cast<size_t>(-1) / size) return nullptr;
  void* p = locus_metis_malloc(count * size);
  if (p) std::memset(p, 0, count * size);
  return p;
}

__attribute__((visibility("hidden"))) void locus_metis_free(void* p) { locus::host_deallocate(p); }

__attribute__((visibility("hidden"))) void* locus_metis_realloc(void* p, size_t n) {
  if (!p) return locus_metis_malloc(n);
  if (n == 0) {
    locus::host_deallocate(p);
    return nullptr;
  }
  void* q = locus_metis_malloc(n);
  if (!q) return nullptr;  // p stays valid, as with realloc
  std::memcpy(q, p, std::min(n, locus::host_allocation_size(p)));
  locus::host_deallocate(p);
  return q;
}

// METIS' messages (its error paths print to stderr before they longjmp): dropped.
__attribute__((visibility("hidden"))) int locus_metis_fprintf(FILE*, const char*, ...) { return 0; }
__attribute__((visibility("hidden"))) int locus_metis_vfprintf(FILE*, const char*, va_list) { return 0; }
__attribute__((visibility("hidden"))) int locus_metis_printf(const char*, ...) { return 0; }
__attribute__((visibility("hidden"))) int locus_metis_fflush(FILE*) { return 0; }

}  // extern "C"
