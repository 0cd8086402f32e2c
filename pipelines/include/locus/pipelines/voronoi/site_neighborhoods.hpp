// Graph-geodesic neighborhoods of sites on a mesh, the start of Lloyd's localized
// solves (thesis §3.6: a solve is restricted to the vertices a cell can reach):
// per site the Dijkstra ball of a radius, or the sites' graph-geodesic Voronoi
// cells from one multi-source Dijkstra. The balls run the patch grower's
// Dijkstra (kernels/include/locus/kernels/mesh/patch_grower.hpp), the cells
// its bucket-queue twin (nearest_seed_buckets.hpp), on the edge lengths
// |x_j - x_i|, seeded at the corners of each site's support at their distance
// |corner - site|.
//
// Thread safety: re-entrant.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"

namespace locus {

// The seeds of a site's Dijkstra: the corners of its support (surface_point_support)
// at their R^3 distance from the site. Returns the count (1 to 3).
int site_seeds(const Mesh& m, const SurfacePoint& s, GrowSeed seeds[3]);

// Lloyd's first neighborhoods (localized solves): per site, the vertices within
// geodesic (Dijkstra) distance `radius` of it, sorted; in parallel, in the
// caller's arena.
std::vector<std::vector<int32_t>> geodesic_neighborhoods(const Mesh& m, const Adjacency& adj,
                                                         std::span<const SurfacePoint> sites, double radius,
                                                         const RunContext& ctx);

// Graph-geodesic Voronoi cells of the sites: label[v] = the site nearest to v
// along edges (label_nearest_seeds_bucketed over every site's seeds, sites in
// id order, where the edge lengths allow a bucket queue, else the heap's
// label_nearest_seeds; exact ties go to the path queued first). -1 where no
// site reaches (a component without sites).
HostVector<int32_t> geodesic_site_cells(const Mesh& m, const Adjacency& adj, std::span<const SurfacePoint> sites);

// Lloyd's method in the graph metric, a cheap start for the heat iterations on
// fine meshes: `iterations` times, the sites' graph-geodesic cells
// (geodesic_site_cells), then every site moves to the vertex of its cell
// nearest (in R^3) to the cell's mass-weighted mean of vertex positions
// (mass: one per vertex). Cells without vertices keep their site. Serial,
// deterministic; ctx is checked for cancellation before each iteration.
// Returns the graph-geodesic cells of the final sites (-1 where no site reaches).
HostVector<int32_t> geodesic_lloyd(const Mesh& m, const Adjacency& adj, std::span<const double> mass,
                                   std::vector<SurfacePoint>& sites, int iterations, const RunContext& ctx = {});

}  // namespace locus
