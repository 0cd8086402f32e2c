// The few BLAS/LAPACK routines locus calls (OpenBLAS), with the thread control
// OpenBLAS adds. Kernels call BLAS single-threaded inside oneTBB tasks: one
// scheduler owns the cores (STYLE.md habit 4).
#pragma once

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

// OpenBLAS runs single-threaded: parallelism comes from oneTBB tasks around
// BLAS calls. The setting is process-wide in OpenBLAS, so it is set (not
// restored) whenever a kernel is about to call BLAS; callers that want threaded
// BLAS for their own code set it again after.
class SingleThreaded {
 public:
  SingleThreaded() {
    if (openblas_get_num_threads() != 1) openblas_set_num_threads(1);
  }
};

}  // namespace locus::blas
