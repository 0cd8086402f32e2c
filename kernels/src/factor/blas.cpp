// BLAS thread count borrowed while locus calls OpenBLAS
// (kernels/include/locus/kernels/factor/blas.hpp says why).
#include "locus/kernels/factor/blas.hpp"

#include <mutex>

namespace locus::blas {

namespace {
std::mutex g_mu;
int g_open = 0;        // scopes open now, on all threads
int g_host_threads = 1;  // the count to restore when the last one closes
}  // namespace

SingleThreaded::SingleThreaded() {
  std::lock_guard<std::mutex> lock(g_mu);
  if (g_open++ == 0) {
    g_host_threads = openblas_get_num_threads();
    if (g_host_threads != 1) openblas_set_num_threads(1);
  }
}

SingleThreaded::~SingleThreaded() {
  std::lock_guard<std::mutex> lock(g_mu);
  if (--g_open == 0 && g_host_threads != 1) openblas_set_num_threads(g_host_threads);
}

}  // namespace locus::blas
