// The caller-owned scratch of one HeatLogMap query (logmap.hpp; thesis
// §6.5-6.6): one struct per step of the query, each filled and read by the
// file named beside it, composed into LogMapWorkspace. A workspace grows to
// the largest query it served and is then reused without allocating; one per
// concurrent query.
#pragma once
#include <cstdint>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_wide.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"

namespace locus {

// What a patch vertex's gradient estimate may be used for. The near field is
// told by the heat from the center, not by the distance, so that the localized
// and the full query see the same sets (logmap_estimator.cpp).
enum class GradientUse : uint8_t {
  Plain,      // the center, or a HeatAverage gradient (chosen or fallback): used as it is
  NearField,  // a log gradient near the center: the lattice corrections apply
  FarField,   // a log gradient beyond the near field: the corrections, and the recenter fit
};

// The heat from every source (logmap_query.cpp): the localized query's wide
// solves over the plan, or the full query's 8-lane whole-mesh solves.
struct LogMapHeatWorkspace {
  WideSolveWorkspace wide;        // localized: up to kMaxWideLanes sources per pass
  HostVector<double> rhs, out;    // localized: one pass's right-hand sides and gathered results
  HostVector<int32_t> row_owner;  // localized, one pass: region index of each row of wide.x, -1 elsewhere
  HostVector<double> table;       // heat rows, one value per source: per region vertex (localized, several
                                  // passes; W * passes per row) or per vertex (full; |S| per row)
  HostVector<double> out8;        // full: one 8-lane batch
  HostVector<double> work;        // full: solve8's work array
  HostVector<double> distance;    // full: n distances
};

// Sources, estimator coefficients and the gradient estimate per patch vertex
// (logmap_estimator.cpp).
struct LogMapEstimatorWorkspace {
  HostVector<int32_t> sources;         // S: the center, its ring ascending, then (two-ring) the second ring ascending
  HostVector<int32_t> sorted_sources;  // S ascending (membership tests)
  HostVector<int32_t> ring2;           // scratch: the two-ring before it is appended to S
  HostVector<double> coef1, coef2;     // 2 * |S|: one-ring and two-ring coefficients; coef2 empty: no two-ring
  HostVector<double> phi;              // 6 * |S|: the two-ring fit's monomials per source
  HostVector<double> cpad;             // coef1 then coef2 (or coef1 again), de-interleaved, padded to SIMD batches
  HostVector<double> rowbuf;           // one heat row, padded to SIMD batches (rows not padded in place)
  HostVector<double> grad;             // 2 per patch vertex: the estimated gradient in the center's frame
  HostVector<GradientUse> use;         // per patch vertex
};

// The edges of dispersion stars in the center's tangent frame (logmap_lattice.cpp).
struct DispersionStarScratch {
  HostVector<double> edges;  // (x, y, weight) per edge
  HostVector<int32_t> ends;  // far end of each edge of the star being added
};

// The lattice correction from the center's star or ring (logmap_lattice.cpp).
struct LogMapLatticeWorkspace {
  DispersionStarScratch star;
  HostVector<double> table;  // direction offset per table angle; empty: no correction
};

// The Path correction (logmap_path.cpp).
struct LogMapPathWorkspace {
  DispersionStarScratch star;
  HostVector<double> r;        // heat radius per patch vertex (from the center's heat)
  HostVector<double> angle;    // first-pass angle per patch vertex
  double rmax = 1;             // largest finite radius (the radius bins' range)
  HostVector<double> moments;  // edge moments per (sector, radius bin) cell, then the center's star
  HostVector<double> table;    // offsets per (sector, radius bin)
};

// From gradients to angles (logmap_angles.cpp).
struct LogMapAnglesWorkspace {
  HostVector<double> theta;  // raw angle per patch vertex, then the recentered gradients' x and y (each padded)
};

struct LogMapWorkspace {
  HeatGeodesicWorkspace geo;  // the patch region, the center's heat and the distance
  SolvePlan plan;             // heat plan, reused across queries (no per-query allocation)
  PlanWorkspace plan_ws;
  LogMapHeatWorkspace heat;
  LogMapEstimatorWorkspace estimator;
  LogMapLatticeWorkspace lattice;
  LogMapPathWorkspace path;
  LogMapAnglesWorkspace angles;
};

}  // namespace locus
