// The weighted polygon-edge Laplacian and its embedding system (thesis §2.3.1
// eq. 2.4, §2.3.2 eq. 2.10); see polygon_laplacian.hpp for the formulation.
#include "locus/kernels/mesh/polygon_laplacian.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Position of (row, col) in a lower CSC matrix with sorted rows; the entry must exist.
int64_t find_slot(const CscMatrix& A, int32_t row, int32_t col) {
  const auto b = A.rowind.begin() + A.colptr[col], e = A.rowind.begin() + A.colptr[col + 1];
  const auto it = std::lower_bound(b, e, row);
  if (it == e || *it != row) fail(ErrorCode::Internal, "embedding system: entry missing from the pattern");
  return it - A.rowind.begin();
}

}  // namespace

EmbeddingSystem::EmbeddingSystem(int32_t nv, std::span<const int32_t> e0, std::span<const int32_t> e1,
                                 std::span<const uint8_t> fixed, const EmbeddingSystemOptions& opt)
    : nv_(nv), e0_(e0.begin(), e0.end()), e1_(e1.begin(), e1.end()), opt_(opt) {
  if (nv < 0 || e0.size() != e1.size() || fixed.size() != static_cast<size_t>(nv))
    fail(ErrorCode::BadInput, "embedding system: inconsistent sizes (vertices, edge ends, fixed flags)");
  const size_t ne = e0.size();
  for (size_t e = 0; e < ne; ++e)
    if (e0[e] < 0 || e0[e] >= nv || e1[e] < 0 || e1[e] >= nv || e0[e] == e1[e])
      fail(ErrorCode::BadInput, "embedding system: edge " + std::to_string(e) + " (" + std::to_string(e0[e]) + ", " +
                                    std::to_string(e1[e]) + ") is out of range or a self loop");
  free_index_.assign(static_cast<size_t>(nv), -1);
  for (int32_t v = 0; v < nv; ++v)
    if (!fixed[v]) free_index_[v] = nfree_++;
  if (nfree_ == 0) fail(ErrorCode::BadInput, "embedding system: every vertex is fixed; nothing to solve");

  // Pattern of K: the diagonal of every free vertex and every free-free edge.
  std::vector<int32_t> ii, jj;
  std::vector<double> vv;
  ii.reserve(static_cast<size_t>(nfree_) + ne);
  jj.reserve(ii.capacity());
  for (int32_t f = 0; f < nfree_; ++f) {
    ii.push_back(f);
    jj.push_back(f);
  }
  for (size_t e = 0; e < ne; ++e) {
    const int32_t a = free_index_[e0[e]], b = free_index_[e1[e]];
    if (a >= 0 && b >= 0) {
      ii.push_back(std::max(a, b));
      jj.push_back(std::min(a, b));
    }
  }
  vv.assign(ii.size(), 1.0);
  K_ = lower_from_triplets(nfree_, ii, jj, vv);
  slot_a_.assign(ne, -1);
  slot_b_.assign(ne, -1);
  slot_off_.assign(ne, -1);
  for (size_t e = 0; e < ne; ++e) {
    const int32_t a = free_index_[e0[e]], b = free_index_[e1[e]];
    if (a >= 0) slot_a_[e] = K_.colptr[a];  // the diagonal leads each column
    if (b >= 0) slot_b_[e] = K_.colptr[b];
    if (a >= 0 && b >= 0) slot_off_[e] = find_slot(K_, std::max(a, b), std::min(a, b));
  }

  auto t0 = std::chrono::steady_clock::now();
  const Ordering ord = order_matrix(K_);
  order_s_ = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  sym_ = analyze(K_, ord);
  analyze_s_ = seconds_since(t0);
}

void EmbeddingSystem::set_weight_floor_rel(double floor_rel) {
  if (!(floor_rel >= 0.0) || !std::isfinite(floor_rel))
    fail(ErrorCode::BadUsage, "embedding system: the weight floor must be finite and >= 0");
  opt_.weight_floor_rel = floor_rel;
}

void EmbeddingSystem::factor(std::span<const double> weights, const RunContext& ctx) {
  const size_t ne = e0_.size();
  if (weights.size() != ne) fail(ErrorCode::BadInput, "embedding system: one weight per edge expected");
  double wmax = 0;
  for (size_t e = 0; e < ne; ++e) {
    if (!std::isfinite(weights[e]) || (!(weights[e] >= 0.0) && !opt_.allow_negative_weights))
      fail(ErrorCode::BadInput, "embedding system: weight of edge " + std::to_string(e) + " (" +
                                    std::to_string(e0_[e]) + ", " + std::to_string(e1_[e]) +
                                    ") is negative or not finite");
    wmax = std::max(wmax, weights[e]);
  }
  if (!(wmax > 0.0) && ne > 0) fail(ErrorCode::BadInput, "embedding system: every weight is zero");
  const double floor = opt_.allow_negative_weights ? -HUGE_VAL : opt_.weight_floor_rel * wmax;
  wa_.resize(ne);
  std::fill(K_.values.begin(), K_.values.end(), 0.0);
  double* val = K_.values.data();
  for (size_t e = 0; e < ne; ++e) {
    const double w = std::max(weights[e], floor);
    wa_[e] = w;
    if (slot_a_[e] >= 0) val[slot_a_[e]] += w;
    if (slot_b_[e] >= 0) val[slot_b_[e]] += w;
    if (slot_off_[e] >= 0) val[slot_off_[e]] -= w;
  }
  if (!factored_) {
    F_ = factorize(sym_, K_, ctx);
    factored_ = true;
  } else {
    refactorize(F_, K_, ctx);
  }
}

void EmbeddingSystem::solve(int dims, const Coords& fixed_pos, const Coords& b, double rhs_scale, Coords& out) const {
  EmbeddingSolveWorkspace ws;
  solve(dims, fixed_pos, b, rhs_scale, out, ws);
}

void EmbeddingSystem::solve(int dims, const Coords& fixed_pos, const Coords& b, double rhs_scale, Coords& out,
                            EmbeddingSolveWorkspace& ws) const {
  if (!factored_) fail(ErrorCode::Internal, "embedding system: solve() before factor()");
  if (dims < 1 || dims > 3) fail(ErrorCode::BadUsage, "embedding system: dims must be 1, 2 or 3");
  const size_t nv = static_cast<size_t>(nv_);
  for (int k = 0; k < dims; ++k) {
    if (fixed_pos[k].size() != nv) fail(ErrorCode::BadInput, "embedding system: fixed positions need nv values");
    if (!b[k].empty() && b[k].size() != nv) fail(ErrorCode::BadInput, "embedding system: b needs nv values or none");
  }
  // Lanes 0..dims-1 carry the coordinates; the other lanes stay zero (padding).
  std::vector<double>& rhs8 = ws.rhs8;
  rhs8.assign(static_cast<size_t>(nfree_) * kLanes, 0.0);
  ws.work.resize(solve_work_size(F_, kLanes));
  for (int32_t v = 0; v < nv_; ++v) {
    const int32_t f = free_index_[v];
    if (f < 0) continue;
    for (int k = 0; k < dims; ++k)
      if (!b[k].empty()) rhs8[static_cast<size_t>(f) * kLanes + k] = -rhs_scale * b[k][v];
  }
  const size_t ne = e0_.size();
  for (size_t e = 0; e < ne; ++e) {
    const int32_t a = free_index_[e0_[e]], c = free_index_[e1_[e]];
    if ((a >= 0) == (c >= 0)) continue;  // both free (in K) or both fixed (irrelevant)
    const int32_t fr = a >= 0 ? a : c;
    const int32_t fixed_v = a >= 0 ? e1_[e] : e0_[e];
    for (int k = 0; k < dims; ++k) rhs8[static_cast<size_t>(fr) * kLanes + k] += wa_[e] * fixed_pos[k][fixed_v];
  }
  solve8(F_, rhs8, ws.work);
  for (int k = 0; k < dims; ++k) {
    out[k].resize(nv);
    for (int32_t v = 0; v < nv_; ++v) {
      const int32_t f = free_index_[v];
      out[k][v] = f < 0 ? fixed_pos[k][v] : rhs8[static_cast<size_t>(f) * kLanes + k];
    }
  }
}

void apply_edge_laplacian(int32_t nv, std::span<const int32_t> e0, std::span<const int32_t> e1,
                          std::span<const double> weights, int dims, const Coords& p, Coords& out) {
  for (int k = 0; k < dims; ++k) out[k].assign(static_cast<size_t>(nv), 0.0);
  for (size_t e = 0; e < e0.size(); ++e) {
    const int32_t a = e0[e], b = e1[e];
    for (int k = 0; k < dims; ++k) {
      const double d = weights[e] * (p[k][b] - p[k][a]);
      out[k][a] += d;
      out[k][b] -= d;
    }
  }
}

}  // namespace locus
