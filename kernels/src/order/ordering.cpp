// Ordering dispatch (kernels/include/locus/kernels/order/ordering.hpp).
#include "locus/kernels/order/ordering.hpp"

#include <cmath>
#include <numeric>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"
#include "locus/kernels/order/metis_ordering.hpp"
#include "locus/kernels/order/minimum_degree.hpp"
#include "locus/kernels/order/nested_dissection.hpp"

namespace locus {

namespace {

// Positions usable for geometric separators: one per column, all finite.
bool usable_positions(const OrderingOptions& opt, int32_t n) {
  const size_t sx = opt.x.size(), sy = opt.y.size(), sz = opt.z.size();
  if (sx == 0 && sy == 0 && sz == 0) return false;
  if (sx != static_cast<size_t>(n) || sy != sx || sz != sx)
    fail(ErrorCode::BadUsage, "order_matrix: " + std::to_string(sx) + "/" + std::to_string(sy) + "/" +
                                  std::to_string(sz) + " vertex positions for a matrix of " + std::to_string(n) +
                                  " columns");
  for (int32_t v = 0; v < n; ++v)
    if (!std::isfinite(opt.x[v]) || !std::isfinite(opt.y[v]) || !std::isfinite(opt.z[v])) return false;
  return true;
}

}  // namespace

Ordering order_matrix(const CscMatrix& A, const OrderingOptions& opt, const RunContext& ctx) {
  if (A.nrows != A.ncols) fail(ErrorCode::BadUsage, "order_matrix: matrix is not square");
  const int32_t n = A.ncols;
  const bool geometric = usable_positions(opt, n);
  Ordering o;
  o.iperm.resize(n);
  using M = OrderingOptions::Method;
  M method = opt.method;
  if (method == M::Auto)
    method = n < opt.amd_min_vertices ? M::Metis : n <= opt.amd_max_vertices ? M::Amd : M::NestedDissection;
  if (method == M::Natural || n <= 2) {
    o.perm.resize(n);
    std::iota(o.perm.begin(), o.perm.end(), 0);
    o.iperm = o.perm;
    return o;
  }
  ctx.check_cancel();
  const AdjacencyGraph g = adjacency_of(A);
  ctx.check_cancel();
  ctx.report(0.0, "ordering");  // a chance to cancel before the first separator
  switch (method) {
    case M::Amd: o.perm = minimum_degree_order(g); break;
    case M::Metis: o.perm = metis_nested_dissection(g, opt.seed, ctx); break;
    default: {
      NestedDissectionOptions nd;
      nd.separator = geometric && opt.separator == OrderingOptions::Separator::Geometric
                         ? NestedDissectionOptions::Separator::Geometric
                         : NestedDissectionOptions::Separator::Metis;
      nd.leaf_size = opt.leaf_size;
      nd.halo = opt.halo;
      nd.metis_seed = opt.seed;
      nd.coarse_levels = opt.coarse_levels;
      nd.coarse_min_vertices = opt.coarse_min_vertices;
      o.perm = nested_dissection(g, opt.x, opt.y, opt.z, nd, ctx);
    }
  }
  ctx.check_cancel();
  for (int32_t k = 0; k < n; ++k) o.iperm[o.perm[k]] = k;
  return o;
}

}  // namespace locus
