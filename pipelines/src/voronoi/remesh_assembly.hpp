// The remesh from a manifold restricted dual (thesis §3.7.1): the dual mesh,
// its raw angles, its optimization on the input and its Hausdorff distance.
// Internal to pipelines/src/voronoi (cvt_remesh.cpp).
#pragma once
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/cvt_remesh.hpp"
#include "locus/pipelines/voronoi/restricted_dual.hpp"

namespace locus {

// r.remesh = the dual of `dual` (a partition of `level`, the input m or its
// subdivision, without defects) at r.lloyd.sites, with r.vertex_site; its raw
// angles (r.dual_*), then, with o.optimize_rounds, its optimization on m (the
// one-triangle components, the collapses to the request, flips and smoothing,
// the splits of thin triangles, the rebalance and the fidelity pull), and with
// o.hausdorff its distance to m through the same grid of m. Times go to
// r.dual_s, r.optimize_s (the grid included) and r.hausdorff_s.
void assemble_remesh(const Mesh& m, const Mesh& level, const RestrictedDual& dual, const RemeshOptions& o,
                     BatchStopwatch& sw, RemeshResult& r);

}  // namespace locus
