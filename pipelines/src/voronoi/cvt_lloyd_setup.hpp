// The set-up of Lloyd's method before its iterations
// (pipelines/include/locus/pipelines/voronoi/cvt_lloyd.hpp; thesis §3.7.1, §3.3):
// every component gets a site, the input is checked, and the operators of the
// cells and the centroids are prepared (in R^3 or in the R^6 lift). Internal to
// pipelines/src/voronoi (cvt_lloyd.cpp).
#pragma once
#include <span>
#include <vector>

#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/parallel/progress_ticker.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/pipelines/voronoi/heat_centroid.hpp"
#include "locus/pipelines/voronoi/voronoi_cell_partition.hpp"
#include "locus/run_context.hpp"

namespace locus {

// Random sites can miss a small component (whose vertices would then get no
// heat): each component without a site takes one from the component with the
// most sites (its last one), placed at the component's lowest vertex. Seeded
// draws stay as they were wherever every component was hit.
void give_every_component_a_site(const Mesh& m, const MeshDerived* given, std::vector<SurfacePoint>& sites);

// The checks of a run: options, the mesh's requirements, the sites, a site in every
// component. given: m's derived data, or null to derive it here (after the
// requirement checks, so the errors come in the same order); `own` holds it then.
const MeshDerived& check_lloyd_input(const Mesh& m, const MeshDerived* given, std::span<const SurfacePoint> sites,
                                     const LloydOptions& opt, MeshDerived& own);

// The operators of one run: the cells' (opt.prepared, or M - t L of the mesh or of
// its R^6 lift) and the centroids' (the same, or with t_centroid_factor a second
// numeric factor on the same symbolic factor), and the face areas in the cells'
// metric. Filled in place: H and Hc may point at H_own and Hc_own.
struct LloydOperators {
  HeatDiffusion H_own, Hc_own;
  const HeatDiffusion* H = nullptr;
  const HeatDiffusion* Hc = nullptr;
  // Hc's masses: Hc->mass, or d.mass for a prepared operator without them (an
  // operator assembled on d lends its masses: command_heat_operator's
  // borrow_mass, 3.3 MB at 416k vertices).
  std::span<const double> mass_c;
  HostVector<double> area_op;  // face areas in the operator's metric (lifted when anisotropic)
};

// Checks the diffusion times and a prepared operator, then builds `ops`; the
// factorization's phases are timed on `sw`. Isotropic: area_r3 (face_areas)
// moves into ops.area_op (left empty; anisotropic runs keep it).
void prepare_lloyd_operators(const Mesh& m, const MeshDerived& d, const LloydOptions& opt, HostVector<double>& area_r3,
                             BatchStopwatch& sw, const RunContext& ctx, LloydOperators& ops);

// The graph-metric iterations of a run (LloydOptions::graph_iterations): the
// given count up to `iterations`, or automatically all but kLargeHeatIterations
// of them on meshes of at least kGraphLloydVertices vertices, else none.
int32_t graph_iterations_of(const LloydOptions& opt, int32_t vertices);

// The centroid fits' geometry and the stars (face areas area_op, moved into them), and beside
// them (a oneTBB task in the caller's arena: they read only the adjacency and
// the masses) the graph-metric iterations on `sites` (geodesic_lloyd), whose
// last cells go to `first` (left empty when graph_iterations is 0). The
// geometry's loops tick `ticker`.
void geometry_beside_graph_start(const Mesh& m, const MeshDerived& d, HostVector<double>&& area_op,
                                 int32_t graph_iterations, ProgressTicker& ticker, const RunContext& ctx,
                                 std::vector<SurfacePoint>& sites, CentroidGeometry& geo, VertexStars& stars,
                                 HostVector<int32_t>& first);

}  // namespace locus
