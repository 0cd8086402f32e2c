// ROI deformation with the factor-once submesh factor (pipelines/include/locus/pipelines/deform/deform.hpp;
// thesis §5.1 eqs. 5.1–5.3, §5.7).
//
// Sequential composition, no flow graph: each stage (operator, global factor,
// region, update, solve) needs all of the previous one; the parallelism lives
// inside the kernels (factorization, update, 8-lane solves).
#include "locus/pipelines/deform/deform.hpp"

#include <Eigen/Sparse>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "locus/core/enum_names.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

using SpMat = Eigen::SparseMatrix<double>;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

SpMat full_of(const CscMatrix& A) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(2 * A.nnz()));
  for (int32_t j = 0; j < A.ncols; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      t.emplace_back(A.rowind[p], j, A.values[p]);
      if (A.rowind[p] != j) t.emplace_back(j, A.rowind[p], A.values[p]);
    }
  SpMat E(A.nrows, A.ncols);
  E.setFromTriplets(t.begin(), t.end());
  return E;
}

CscMatrix lower_of(const SpMat& E) {
  std::vector<int32_t> I, J;
  std::vector<double> V;
  for (int k = 0; k < E.outerSize(); ++k)
    for (SpMat::InnerIterator it(E, k); it; ++it)
      if (it.row() >= it.col()) {
        I.push_back(static_cast<int32_t>(it.row()));
        J.push_back(static_cast<int32_t>(it.col()));
        V.push_back(it.value());
      }
  return lower_from_triplets(static_cast<int32_t>(E.rows()), I, J, V);
}

// The values of a full symmetric Eigen matrix on the lower pattern of P;
// Internal error if E has a nonzero outside it.
CscMatrix on_pattern(const SpMat& E, const CscMatrix& P) {
  CscMatrix R = P;
  std::vector<double> work(static_cast<size_t>(P.nrows), 0.0);
  std::vector<int64_t> mark(static_cast<size_t>(P.nrows), -1);
  for (int32_t j = 0; j < P.ncols; ++j) {
    for (int64_t p = P.colptr[j]; p < P.colptr[j + 1]; ++p) mark[P.rowind[p]] = j;
    for (SpMat::InnerIterator it(E, j); it; ++it)
      if (it.row() >= j) {
        if (mark[it.row()] != j && it.value() != 0.0)
          fail(ErrorCode::Internal, "deform: energy entry (" + std::to_string(it.row()) + ", " + std::to_string(j) +
                                        ") outside the factored pattern");
        work[it.row()] = it.value();
      }
    for (int64_t p = P.colptr[j]; p < P.colptr[j + 1]; ++p) {
      R.values[p] = work[P.rowind[p]];
      work[P.rowind[p]] = 0.0;
    }
  }
  return R;
}

}  // namespace

constexpr EnumNames<DeformEnergy, 2> kDeformEnergies{
    {{DeformEnergy::Laplacian, "laplacian"}, {DeformEnergy::Bilaplacian, "bilaplacian"}}};

DeformEnergy parse_deform_energy(std::string_view name) { return parse_enum_name(name, kDeformEnergies, "energy"); }

const char* deform_energy_name(DeformEnergy e) { return enum_name(e, kDeformEnergies); }

DeformMatrices deform_matrices(const Mesh& m, DeformEnergy energy, double rel) {
  if (!(rel > 0) || !std::isfinite(rel)) fail(ErrorCode::BadUsage, "deform: regularization must be a positive number");
  check_requirements(m, MeshRequirements{});
  CscMatrix Lp = cotan_laplacian(m);
  for (double& v : Lp.values) v = -v;
  const auto M = lumped_mass(m);
  double trL = 0, trM = 0;
  for (int32_t j = 0; j < Lp.ncols; ++j) {
    if (Lp.colptr[j] == Lp.colptr[j + 1] || Lp.rowind[Lp.colptr[j]] != j)
      fail(ErrorCode::Internal, "deform: the cotan Laplacian has no diagonal entry in column " + std::to_string(j));
    trL += Lp.values[Lp.colptr[j]];  // lower-stored, sorted: the diagonal comes first
    trM += M[j];
  }
  DeformMatrices d;
  d.eps = rel * trL / trM;
  if (!(d.eps > 0) || !std::isfinite(d.eps)) fail(ErrorCode::BadInput, "deform: the mesh has no area");
  CscMatrix K = Lp;
  for (int32_t j = 0; j < K.ncols; ++j) K.values[K.colptr[j]] += d.eps * M[j];
  if (energy == DeformEnergy::Laplacian) {
    d.A = std::move(K);
    d.E = std::move(Lp);
    return d;
  }
  Eigen::VectorXd minv(static_cast<Eigen::Index>(M.size()));
  for (size_t i = 0; i < M.size(); ++i) minv[static_cast<Eigen::Index>(i)] = 1.0 / M[i];
  const SpMat Kf = full_of(K), Lf = full_of(Lp);
  const SpMat A = Kf * minv.asDiagonal() * Kf;
  const SpMat E = Lf * minv.asDiagonal() * Lf;
  d.A = lower_of(A);
  d.E = on_pattern(E, d.A);
  return d;
}

DeformOperator prepare_deform_operator(const Mesh& m, DeformEnergy energy, double rel, const RunContext& ctx) {
  DeformOperator op;
  op.energy = energy;
  auto t0 = std::chrono::steady_clock::now();
  op.mats = deform_matrices(m, energy, rel);
  op.operator_s = seconds_since(t0);
  ctx.check_cancel();
  t0 = std::chrono::steady_clock::now();
  const Ordering ord = order_matrix(op.mats.A);
  op.order_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  auto S = analyze(op.mats.A, ord);
  op.analyze_s = seconds_since(t0);
  ctx.check_cancel();
  t0 = std::chrono::steady_clock::now();
  op.L = factorize(std::move(S), op.mats.A, ctx);
  op.factor_s = seconds_since(t0);
  return op;
}

DeformRegion make_deform_region(const Adjacency& adj, int32_t roi_seed, double roi_fraction, int32_t handle_vertex,
                                int32_t handle_ring) {
  const int32_t n = static_cast<int32_t>(adj.offsets.size()) - 1;
  if (!(roi_fraction > 0 && roi_fraction <= 1))
    fail(ErrorCode::BadUsage, "ROI fraction must be in (0, 1], got " + std::to_string(roi_fraction));
  if (handle_vertex < 0 || handle_vertex >= n)
    fail(ErrorCode::BadUsage, "handle vertex " + std::to_string(handle_vertex) + " is out of range [0, " + std::to_string(n) + ")");
  if (handle_ring < 0) fail(ErrorCode::BadUsage, "handle ring must be >= 0");
  const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(roi_fraction * n)));
  DeformRegion r;
  if (roi_seed < 0 || roi_seed >= n)
    fail(ErrorCode::BadUsage, "seed vertex " + std::to_string(roi_seed) + " is out of range [0, " + std::to_string(n) + ")");
  r.roi = grow_ring_vertices(adj, roi_seed, count);  // BFS rings (patch_grower.hpp)
  std::vector<uint8_t> in_roi(n, 0);
  for (int32_t v : r.roi) in_roi[v] = 1;
  if (!in_roi[handle_vertex])
    fail(ErrorCode::BadUsage, "handle vertex " + std::to_string(handle_vertex) + " is not in the region of interest (" +
                                  std::to_string(r.roi.size()) + " vertices around vertex " + std::to_string(roi_seed) + ")");
  // k-ring by BFS over the mesh graph, kept where it lies in the ROI.
  std::vector<int32_t> depth(n, -1), ring{handle_vertex};
  depth[handle_vertex] = 0;
  for (size_t h = 0; h < ring.size(); ++h) {
    const int32_t v = ring[h];
    if (depth[v] == handle_ring) continue;
    for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
      const int32_t w = adj.neighbors[p];
      if (depth[w] < 0) {
        depth[w] = depth[v] + 1;
        ring.push_back(w);
      }
    }
  }
  std::vector<uint8_t> in_handle(n, 0);
  for (int32_t v : ring)
    if (in_roi[v]) in_handle[v] = 1;
  std::sort(r.roi.begin(), r.roi.end());
  for (int32_t v : r.roi) (in_handle[v] ? r.handle : r.free).push_back(v);
  if (r.free.empty()) fail(ErrorCode::BadUsage, "the handle covers the whole region of interest: no free vertex to solve for");
  return r;
}

DeformSystem prepare_deform_system(const DeformOperator& op, const DeformRegion& region, const RunContext& ctx) {
  DeformSystem sys;
  const auto t0 = std::chrono::steady_clock::now();
  sys.sub = update_factor(op.L, op.mats.A, region.free, ctx);
  sys.update_s = seconds_since(t0);
  sys.E_FF = principal_submatrix(op.mats.E, sys.sub.vertices);
  const CscMatrix& E = op.mats.E;
  const int32_t n = E.ncols, nf = static_cast<int32_t>(sys.sub.vertices.size());
  std::vector<int32_t> local(n, -1);
  for (int32_t a = 0; a < nf; ++a) local[sys.sub.vertices[a]] = a;
  sys.coupling_ptr.assign(static_cast<size_t>(nf) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int64_t> next;
    if (pass == 1) {
      for (int32_t a = 0; a < nf; ++a) sys.coupling_ptr[a + 1] += sys.coupling_ptr[a];
      sys.coupling_vertex.resize(static_cast<size_t>(sys.coupling_ptr[nf]));
      sys.coupling_value.resize(static_cast<size_t>(sys.coupling_ptr[nf]));
      next.assign(sys.coupling_ptr.begin(), sys.coupling_ptr.end() - 1);
    }
    for (int32_t j = 0; j < n; ++j)
      for (int64_t p = E.colptr[j]; p < E.colptr[j + 1]; ++p) {
        const int32_t i = E.rowind[p];
        const int32_t a = local[i], b = local[j];
        if ((a >= 0) == (b >= 0)) continue;  // both free or both known
        const int32_t f = a >= 0 ? a : b, known = a >= 0 ? j : i;
        if (pass == 0) {
          ++sys.coupling_ptr[f + 1];
        } else {
          sys.coupling_vertex[next[f]] = known;
          sys.coupling_value[next[f]++] = E.values[p];
        }
      }
  }
  return sys;
}

Mesh handle_target(const Mesh& rest, const DeformRegion& region, const std::array<double, 3>& offset) {
  Mesh t = rest;
  const int32_t n = rest.num_vertices();
  for (int32_t v : region.handle) {
    if (v < 0 || v >= n) fail(ErrorCode::BadUsage, "handle_target: region does not match the mesh");
    t.x[v] = rest.x[v] + offset[0];
    t.y[v] = rest.y[v] + offset[1];
    t.z[v] = rest.z[v] + offset[2];
  }
  return t;
}

DeformSolveStats solve_deformation(const NumericFactor& F, const DeformSystem& sys, const Mesh& rest,
                                   const Mesh& target, Mesh& out) {
  const int32_t nf = static_cast<int32_t>(sys.sub.vertices.size());
  if (F.n() != nf) fail(ErrorCode::BadUsage, "solve_deformation: factor size differs from the free set");
  const int32_t n = rest.num_vertices();
  if (target.num_vertices() != n) fail(ErrorCode::BadUsage, "solve_deformation: target and rest differ in size");
  out = target;  // known vertices: bit for bit
  const HostVector<double>* T[3] = {&target.x, &target.y, &target.z};
  const HostVector<double>* R[3] = {&rest.x, &rest.y, &rest.z};
  // b = -E_FB d_B, d = target - rest; x, y, z in lanes 0..2 of a row-interleaved 8-lane block.
  std::vector<double> b8(static_cast<size_t>(nf) * kLanes, 0.0);
  for (int32_t a = 0; a < nf; ++a)
    for (int64_t q = sys.coupling_ptr[a]; q < sys.coupling_ptr[a + 1]; ++q) {
      const int32_t w = sys.coupling_vertex[q];
      if (w < 0 || w >= n) fail(ErrorCode::BadUsage, "solve_deformation: mesh does not match the system");
      for (int c = 0; c < 3; ++c)
        b8[static_cast<size_t>(a) * kLanes + c] -= sys.coupling_value[q] * ((*T[c])[w] - (*R[c])[w]);
    }
  std::vector<double> work(solve_work_size(F, kLanes));
  std::vector<double> x8 = b8;
  solve8(F, x8, work);

  // Iterative refinement towards the exact energy: r = b - E_FF x, x += A_FF^{-1} r.
  std::vector<double> lane(static_cast<size_t>(nf)), Ex(static_cast<size_t>(nf)), r8(x8.size());
  auto residual8 = [&](std::vector<double>& r, double* worst_rel) {
    std::fill(r.begin(), r.end(), 0.0);
    double worst = 0;
    for (int c = 0; c < 3; ++c) {
      for (int32_t a = 0; a < nf; ++a) lane[a] = x8[static_cast<size_t>(a) * kLanes + c];
      symmetric_multiply(sys.E_FF, lane.data(), Ex.data());
      double rn = 0, bn = 0;
      for (int32_t a = 0; a < nf; ++a) {
        const size_t k = static_cast<size_t>(a) * kLanes + c;
        r[k] = b8[k] - Ex[a];
        rn += r[k] * r[k];
        bn += b8[k] * b8[k];
      }
      worst = std::max(worst, bn > 0 ? std::sqrt(rn / bn) : std::sqrt(rn));
    }
    if (worst_rel) *worst_rel = worst;
  };
  DeformSolveStats st;
  double prev = HUGE_VAL;
  for (int step = 0; step < 200; ++step) {
    residual8(r8, nullptr);
    solve8(F, r8, work);
    double dmax = 0, xmax = 0;
    for (int32_t a = 0; a < nf; ++a)
      for (int c = 0; c < 3; ++c) {
        const size_t k = static_cast<size_t>(a) * kLanes + c;
        x8[k] += r8[k];
        dmax = std::max(dmax, std::abs(r8[k]));
        xmax = std::max(xmax, std::abs(x8[k]));
      }
    const double corr = xmax > 0 ? dmax / xmax : dmax;
    st.refinement_steps = step + 1;
    st.last_correction = corr;
    if (!std::isfinite(corr)) break;
    if (corr <= 1e-14) break;
    if (corr > 0.7 * prev) {  // no longer contracting: the rounding floor, or divergence
      if (corr <= 1e-9) break;
      fail(ErrorCode::Numerical, "deformation does not converge (relative correction " + std::to_string(corr) +
                                     " after " + std::to_string(step + 1) +
                                     " refinement steps): a free region touches no fixed vertex, or the "
                                     "regularization is too large for this region");
    }
    prev = corr;
  }
  if (!(st.last_correction <= 1e-9))
    fail(ErrorCode::Numerical, "deformation did not converge (relative correction " + std::to_string(st.last_correction) + ")");
  residual8(r8, &st.residual);
  for (int32_t a = 0; a < nf; ++a) {
    const int32_t v = sys.sub.vertices[a];
    out.x[v] = rest.x[v] + x8[static_cast<size_t>(a) * kLanes + 0];
    out.y[v] = rest.y[v] + x8[static_cast<size_t>(a) * kLanes + 1];
    out.z[v] = rest.z[v] + x8[static_cast<size_t>(a) * kLanes + 2];
  }
  return st;
}

}  // namespace locus
