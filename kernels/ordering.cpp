// Fill-reducing ordering by METIS nested dissection (kernels/ordering.hpp).
//
// The graph is the off-diagonal pattern of the symmetric matrix, built in
// O(nnz) by counting. METIS runs with a fixed seed so the ordering, and with
// it every factor and every result downstream, is reproducible.
//
// METIS runs on one thread: its random generator is process-global (GKlib),
// so concurrent METIS calls on the two halves of a top-level separator gave
// orderings that changed with the thread count (measured: nnz(L) 851,988 vs
// 854,139 on a 160x160 grid) — determinism wins over the ~1.8x it would save.
// Graph compression is off: mesh graphs have no vertices with identical
// neighbourhoods, so METIS' detection pass only costs time.
#include "kernels/ordering.hpp"

#include <metis.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <thread>

#include "locus/error.hpp"

namespace locus {

namespace {

// Full symmetric adjacency (both triangles, no diagonal) of a lower-stored matrix.
void matrix_graph(const CscMatrix& A, std::vector<idx_t>& xadj, std::vector<idx_t>& adjncy) {
  const int32_t n = A.ncols;
  std::vector<idx_t> deg(static_cast<size_t>(n) + 1, 0);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (i != j) { ++deg[i]; ++deg[j]; }
    }
  xadj.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t j = 0; j < n; ++j) xadj[j + 1] = xadj[j] + deg[j];
  adjncy.resize(static_cast<size_t>(xadj[n]));
  std::vector<idx_t> pos(xadj.begin(), xadj.end() - 1);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (i != j) { adjncy[pos[i]++] = j; adjncy[pos[j]++] = i; }
    }
}

// Never destroyed: an abandoned call may still hold it while the process exits.
std::mutex& metis_mutex() {
  static std::mutex* m = new std::mutex;
  return *m;
}

// Everything one METIS call touches, shared with a helper thread that may outlive the caller.
struct MetisJob {
  std::vector<idx_t> xadj, adjncy;
  idx_t options[METIS_NOPTIONS];
  idx_t nv = 0;
  std::vector<int32_t> perm, iperm;
  int rc = METIS_OK;
  std::mutex m;
  std::condition_variable cv;
  bool done = false;

  void run() {
    std::lock_guard<std::mutex> serial(metis_mutex());
    rc = METIS_NodeND(&nv, xadj.data(), adjncy.data(), nullptr, options, perm.data(), iperm.data());
  }
};

}  // namespace

Ordering order_matrix(const CscMatrix& A, const OrderingOptions& opt, const RunContext& ctx) {
  if (A.nrows != A.ncols) fail(ErrorCode::BadUsage, "order_matrix: matrix is not square");
  const int32_t n = A.ncols;
  Ordering o;
  o.perm.resize(n);
  o.iperm.resize(n);
  if (opt.method == OrderingOptions::Method::Natural || n <= 2) {
    std::iota(o.perm.begin(), o.perm.end(), 0);
    o.iperm = o.perm;
    return o;
  }
  auto job = std::make_shared<MetisJob>();
  matrix_graph(A, job->xadj, job->adjncy);
  if (job->xadj[n] == 0) {  // no edges: any order has no fill
    std::iota(o.perm.begin(), o.perm.end(), 0);
    o.iperm = o.perm;
    return o;
  }
  METIS_SetDefaultOptions(job->options);
  job->options[METIS_OPTION_NUMBERING] = 0;
  job->options[METIS_OPTION_SEED] = opt.seed;
  job->options[METIS_OPTION_COMPRESS] = 0;
  job->nv = n;
  // METIS manual: row i of the permuted matrix is row perm[i] of the original,
  // which is our convention too.
  job->perm.resize(n);
  job->iperm.resize(n);
  ctx.check_cancel();
  if (!ctx.cancel) {
    job->run();
  } else {
    std::thread worker([job] {
      job->run();
      {
        std::lock_guard<std::mutex> lk(job->m);
        job->done = true;
      }
      job->cv.notify_all();
    });
    std::unique_lock<std::mutex> lk(job->m);
    while (!job->done) {
      if (ctx.cancelled()) {
        lk.unlock();
        worker.detach();  // finishes on its own; `job` lives until then
        fail(ErrorCode::Cancelled, "cancelled (during the METIS ordering)");
      }
      job->cv.wait_for(lk, std::chrono::milliseconds(5));
    }
    lk.unlock();
    worker.join();
  }
  const int rc = job->rc;
  o.perm = std::move(job->perm);
  o.iperm = std::move(job->iperm);
  if (rc != METIS_OK)
    fail(rc == METIS_ERROR_MEMORY ? ErrorCode::ResourceLimit : ErrorCode::Internal,
         "METIS_NodeND failed with status " + std::to_string(rc) + " on a graph of " + std::to_string(n) + " vertices");
  return o;
}

}  // namespace locus
