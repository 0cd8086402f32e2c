// The contenders of `locus-bench factor` (factor_peers.hpp).
// Eigen/MetisSupport uses std::cerr without including <iostream>.
#include <iostream>
#include <Eigen/MetisSupport>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <limits>

#include "locus/error.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "tools/bench/factor_peers.hpp"

#ifdef LOCUS_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace locus::bench::factor {

using cli::Stopwatch;

double rel_diff(const std::vector<double>& a, const std::vector<double>& ref) {
  double d = 0, r = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    d += (a[i] - ref[i]) * (a[i] - ref[i]);
    r += ref[i] * ref[i];
  }
  return r > 0 ? std::sqrt(d / r) : std::sqrt(d);
}

// ---------------------------------------------------------------- locus ----

void run_locus(const CscMatrix& A, const OrderingOptions& oo, const Rhs& rhs, const RunContext& ctx, PeerRun& out) {
  const size_t n = static_cast<size_t>(rhs.n);
  Stopwatch sw;
  const Ordering ord = order_matrix(A, oo, ctx);
  out.order_s.push_back(sw.seconds());
  sw.restart();
  std::shared_ptr<const SymbolicFactor> sym = analyze(A, ord, {}, ctx);
  out.symbolic_s.push_back(sw.seconds());
  out.analyze_s.push_back(out.order_s.back() + out.symbolic_s.back());
  ctx.check_cancel();

  sw.restart();
  NumericFactor F = factorize(sym, A, ctx);
  out.factor_first_s.push_back(sw.seconds());
  ctx.check_cancel();
  sw.restart();
  refactorize(F, A, ctx);
  out.factor_repeat_s.push_back(sw.seconds());
  ctx.check_cancel();

  std::vector<double> work(std::max(solve_work_size(F, 1), solve_work_size(F, kLanes)));
  out.x = rhs.b;
  sw.restart();
  solve(F, out.x, work);
  out.solve_s.push_back(sw.seconds());

  // locus takes 8 lanes row-interleaved (rhs[row*8 + lane]).
  std::vector<double> x8(n * kLanes);
  for (size_t i = 0; i < n; ++i)
    for (int l = 0; l < kLanes; ++l) x8[i * kLanes + l] = rhs.b8[l * n + i];
  sw.restart();
  solve8(F, x8, work);
  out.solve8_s.push_back(sw.seconds());
  out.x8.resize(n * kLanes);
  for (size_t i = 0; i < n; ++i)
    for (int l = 0; l < kLanes; ++l) out.x8[l * n + i] = x8[i * kLanes + l];

  out.nnz_L = static_cast<double>(sym->nnz_exact);
  out.nnz_L_stored = static_cast<double>(sym->nnz_L);
  out.extra["supernodes"] = sym->ns;
  out.extra["etree_height"] = sym->etree_height;
  out.extra["super_etree_height"] = sym->super_etree_height;
}

// ---------------------------------------------------------------- Eigen ----

void run_eigen(const CscMatrix& A, const Rhs& rhs, PeerRun& out) {
  using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  const int n = rhs.n;
  std::vector<int> colptr(A.colptr.begin(), A.colptr.end());
  const Eigen::Map<const SpMat> Am(n, n, static_cast<int>(A.nnz()), colptr.data(), A.rowind.data(), A.values.data());
  const SpMat Ae = Am;  // Eigen's solvers read only the lower triangle (UpLo = Lower)

  Eigen::SimplicialLLT<SpMat, Eigen::Lower, Eigen::MetisOrdering<int>> llt;
  Stopwatch sw;
  llt.analyzePattern(Ae);
  out.analyze_s.push_back(sw.seconds());
  sw.restart();
  llt.factorize(Ae);
  out.factor_first_s.push_back(sw.seconds());
  if (llt.info() != Eigen::Success) fail(ErrorCode::Numerical, "Eigen SimplicialLLT: matrix is not positive definite");
  sw.restart();
  llt.factorize(Ae);
  out.factor_repeat_s.push_back(sw.seconds());

  const Eigen::Map<const Eigen::VectorXd> b(rhs.b.data(), n);
  Eigen::VectorXd x(n);
  sw.restart();
  x = llt.solve(b);
  out.solve_s.push_back(sw.seconds());
  const Eigen::Map<const Eigen::MatrixXd> B8(rhs.b8.data(), n, kLanes);
  Eigen::MatrixXd X8(n, kLanes);
  sw.restart();
  X8 = llt.solve(B8);
  out.solve8_s.push_back(sw.seconds());

  out.x.assign(x.data(), x.data() + n);
  out.x8.assign(X8.data(), X8.data() + static_cast<size_t>(n) * kLanes);
  out.nnz_L = static_cast<double>(llt.matrixL().nestedExpression().nonZeros());
  out.nnz_L_stored = out.nnz_L;
}

// -------------------------------------------------------------- CHOLMOD ----

#ifdef LOCUS_HAVE_CHOLMOD
namespace {

const char* cholmod_ordering_name(int ordering) {
  switch (ordering) {
    case CHOLMOD_NATURAL: return "natural";
    case CHOLMOD_GIVEN: return "given";
    case CHOLMOD_AMD: return "amd";
    case CHOLMOD_METIS: return "metis";
    case CHOLMOD_NESDIS: return "nesdis";
    case CHOLMOD_COLAMD: return "colamd";
    case CHOLMOD_POSTORDERED: return "postordered";
    default: return "unknown";
  }
}

// Owns a cholmod_common and everything allocated with it, so that an error
// thrown half way frees what was allocated.
class Cholmod {
 public:
  explicit Cholmod(const std::string& ordering) {
    cholmod_start(&c_);
    c_.supernodal = CHOLMOD_SUPERNODAL;  // supernodal always, as locus
    // "default" keeps CHOLMOD's own choice; "metis"/"amd" force one method, so
    // the analyze time can be compared against the same kind of ordering.
    if (ordering != "default") {
      c_.nmethods = 1;
      c_.method[0].ordering = ordering == "metis" ? CHOLMOD_METIS : CHOLMOD_AMD;
      c_.postorder = 1;
    }
  }
  ~Cholmod() {
    if (L_) cholmod_free_factor(&L_, &c_);
    if (A_) cholmod_free_sparse(&A_, &c_);
    for (cholmod_dense** d : {&B_, &B8_, &X_, &X8_, &Y_, &E_})
      if (*d) cholmod_free_dense(d, &c_);
    cholmod_finish(&c_);
  }
  Cholmod(const Cholmod&) = delete;
  Cholmod& operator=(const Cholmod&) = delete;

  void run(const CscMatrix& A, const Rhs& rhs, PeerRun& out) {
    const size_t n = static_cast<size_t>(rhs.n);
    if (A.nnz() > std::numeric_limits<int>::max())
      fail(ErrorCode::ResourceLimit, "CHOLMOD peer: nnz(A) exceeds 32-bit indices");
    A_ = cholmod_allocate_sparse(n, n, static_cast<size_t>(A.nnz()), /*sorted=*/1, /*packed=*/1, /*stype=*/-1,
                                 CHOLMOD_REAL, &c_);
    check("cholmod_allocate_sparse");
    int* p = static_cast<int*>(A_->p);
    int* i = static_cast<int*>(A_->i);
    double* x = static_cast<double*>(A_->x);
    for (size_t k = 0; k <= n; ++k) p[k] = static_cast<int>(A.colptr[k]);
    std::copy(A.rowind.begin(), A.rowind.end(), i);
    std::copy(A.values.begin(), A.values.end(), x);

    Stopwatch sw;
    L_ = cholmod_analyze(A_, &c_);
    out.analyze_s.push_back(sw.seconds());
    check("cholmod_analyze");
    // Its ordering alone, timed by a second call of the method it chose:
    // symbolic_s is the rest of cholmod_analyze (postorder, counts, supernodes).
    std::vector<int> perm(n);
    sw.restart();
    if (L_->ordering == CHOLMOD_METIS)
      cholmod_metis(A_, nullptr, 0, /*postorder=*/1, perm.data(), &c_);
    else
      cholmod_amd(A_, nullptr, 0, perm.data(), &c_);
    out.order_s.push_back(std::min(sw.seconds(), out.analyze_s.back()));
    out.symbolic_s.push_back(out.analyze_s.back() - out.order_s.back());
    check("cholmod ordering");
    sw.restart();
    cholmod_factorize(A_, L_, &c_);
    out.factor_first_s.push_back(sw.seconds());
    check("cholmod_factorize");
    sw.restart();
    cholmod_factorize(A_, L_, &c_);
    out.factor_repeat_s.push_back(sw.seconds());
    check("cholmod_factorize (repeat)");

    B_ = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &c_);
    B8_ = cholmod_allocate_dense(n, kLanes, n, CHOLMOD_REAL, &c_);
    check("cholmod_allocate_dense");
    std::copy(rhs.b.begin(), rhs.b.end(), static_cast<double*>(B_->x));
    std::copy(rhs.b8.begin(), rhs.b8.end(), static_cast<double*>(B8_->x));
    // cholmod_solve2 with caller-owned X, Y, E (as locus's solves take a work
    // buffer): a first untimed call sizes them, the timed call reuses them.
    cholmod_solve2(CHOLMOD_A, L_, B_, nullptr, &X_, nullptr, &Y_, &E_, &c_);
    sw.restart();
    cholmod_solve2(CHOLMOD_A, L_, B_, nullptr, &X_, nullptr, &Y_, &E_, &c_);
    out.solve_s.push_back(sw.seconds());
    check("cholmod_solve2");
    cholmod_solve2(CHOLMOD_A, L_, B8_, nullptr, &X8_, nullptr, &Y_, &E_, &c_);
    sw.restart();
    cholmod_solve2(CHOLMOD_A, L_, B8_, nullptr, &X8_, nullptr, &Y_, &E_, &c_);
    out.solve8_s.push_back(sw.seconds());
    check("cholmod_solve2 (8 lanes)");

    const double* xs = static_cast<const double*>(X_->x);
    const double* x8s = static_cast<const double*>(X8_->x);
    out.x.assign(xs, xs + n);
    out.x8.assign(x8s, x8s + n * kLanes);
    out.nnz_L = c_.lnz;
    out.nnz_L_stored = static_cast<double>(L_->xsize);
    out.extra["ordering"] = cholmod_ordering_name(L_->ordering);
    out.extra["supernodes"] = static_cast<int64_t>(L_->nsuper);
    out.extra["is_supernodal"] = L_->is_super != 0;
  }

 private:
  void check(const char* what) {
    if (c_.status == CHOLMOD_NOT_POSDEF)
      fail(ErrorCode::Numerical, std::string("CHOLMOD: not positive definite (") + what + ")");
    if (c_.status != CHOLMOD_OK) fail(ErrorCode::Internal, std::string(what) + " failed with status " + std::to_string(c_.status));
  }
  cholmod_common c_{};
  cholmod_sparse* A_ = nullptr;
  cholmod_factor* L_ = nullptr;
  cholmod_dense *B_ = nullptr, *B8_ = nullptr, *X_ = nullptr, *X8_ = nullptr, *Y_ = nullptr, *E_ = nullptr;
};

}  // namespace

void run_cholmod(const std::string& ordering, const CscMatrix& A, const Rhs& rhs, PeerRun& out) {
  Cholmod ch(ordering);
  ch.run(A, rhs, out);
}
#endif

}  // namespace locus::bench::factor
