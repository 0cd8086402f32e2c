// The few BLAS/LAPACK routines locus calls (OpenBLAS), with the thread control
// OpenBLAS adds. Kernels call BLAS single-threaded inside oneTBB tasks: one
// scheduler owns the cores (STYLE.md habit 4).
#pragma once
#include "locus/core/non_copyable.hpp"

extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a, const int* lda,
            double* x, const int* incx);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a, const int* lda,
            const double* x, const int* incx, const double* beta, double* y, const int* incy);
void dtrtri_(const char* uplo, const char* diag, const int* n, double* a, const int* lda, int* info);
void dlauum_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void openblas_set_num_threads(int num_threads);
int openblas_get_num_threads(void);
}

namespace locus::blas {

// OpenBLAS runs single-threaded while locus calls it: parallelism comes from
// oneTBB tasks around BLAS calls. OpenBLAS' thread count is process-wide (the
// Debian 12 version has no per-thread setting), so it is borrowed, not taken:
// the first scope to open (on any thread) saves the host's
// count and sets 1, the last to close restores the saved count. While locus
// runs, a host thread calling BLAS itself sees 1; after the call, what it set.
class SingleThreaded : NonCopyable {
 public:
  SingleThreaded();
  ~SingleThreaded();
};

}  // namespace locus::blas
