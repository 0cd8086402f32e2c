// The subcommands of `locus-bench`, one file each (tools/bench/bench_<name>.cpp).
// They share the grammar of the `locus` tool (tools/cli/cli_common.hpp).
#pragma once
#include <string>

#include "locus/kernels/order/ordering.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::bench {

// `locus-bench factor`: locus vs CHOLMOD vs Eigen on one operator.
void register_factor_bench(cli::CommandTable& table);
void register_logmap_bench(cli::CommandTable& table);             // logmap: localized vs full vs DEM timings
void register_logmap_accuracy_bench(cli::CommandTable& table);    // logmap-accuracy on analytic surfaces
void register_geodesic_accuracy_bench(cli::CommandTable& table);  // geodesic-accuracy on analytic surfaces
void register_submesh_bench(cli::CommandTable& table);  // factor-once update vs refactoring
void register_local_bench(cli::CommandTable& table);  // local: heat values, ADF at all vertices, patch parameterization
void register_voronoi_bench(cli::CommandTable& table);  // voronoi-convergence (thesis Fig. 3.1)
void register_stress_bench(cli::CommandTable& table);  // stress: concurrent Session queries, RSS, cancellation; --big
void register_cancel_bench(cli::CommandTable& table);  // cancel: C API cancel latency of the first geodesic query
void register_remesh_bench(cli::CommandTable& table);  // remesh: CVT remeshing vs geogram's published figures
void register_robust_bench(cli::CommandTable& table);  // robust: first answer on the robust vs the cotan operator
void register_skinning_bench(cli::CommandTable& table);  // skinning: sampled vs exact skinning weights

// The ordering a bench names: auto (the library's default), metis
// (METIS_NodeND, the former default), amd, nd (nested
// dissection), nd_geometric (plane-cut separators, given positions),
// nd_nohalo (AMD leaves without their halo), nd_metis (METIS on every
// node's own graph). BadUsage for any other name.
OrderingOptions ordering_by_name(const std::string& name);

}  // namespace locus::bench
