// Graph-geodesic Voronoi labels by a bucket queue (Dial's algorithm), the
// cells of Lloyd's graph-metric iterations (thesis §3.6; pipelines/voronoi
// site_neighborhoods.hpp geodesic_lloyd).
//
// The same labels as label_nearest_seeds_by_positions (patch_grower.hpp), whose
// binary heap costs most of a multi-source Dijkstra over a whole mesh (~0.6 s
// at 416k vertices, most of it the heap's cache misses). Here the tentative
// distances go into buckets of width w just below the shortest edge: a vertex
// of the lowest bucket cannot be improved by another of that bucket (any path
// through one more edge is longer by more than w), so a bucket's vertices are
// final when it is reached, and each is taken in the order it was queued.
// Every distance is the heap's, bit for bit: both take the minimum over the
// same relaxations. A label can differ only where two paths tie exactly
// (the heap keeps the first to arrive in its own order). A bucket's vertices
// offer their neighbors shorter distances in parallel (the caller's oneTBB
// arena); the offers are applied in queue order, so the labels are the same
// for any number of threads.
//
// Needs the spread of edge lengths to be bounded: prepare_seed_buckets
// returns an unusable plan (usable() false) when an edge has zero length or
// the longest edge exceeds kMaxBucketSpread shortest ones; callers then take
// the heap. Thread safety: re-entrant; a workspace per concurrent call.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/mesh.hpp"

namespace locus {

inline constexpr double kMaxBucketSpread = 4096;

// The bucket width and count of one mesh (its edge lengths' range), computed
// once for many labellings.
struct SeedBucketPlan {
  double width = 0;     // just below the shortest edge; 0 when unusable
  int32_t buckets = 0;  // the ring of buckets: enough for the longest edge
  bool usable() const { return width > 0; }
};

struct SeedBucketWorkspace {
  struct Offer {
    double distance;
    int32_t to, from;
  };
  HostVector<double> dist;
  HostVector<uint8_t> done;
  std::vector<HostVector<int32_t>> bucket;  // the ring: a front's vertices each
  std::vector<HostVector<Offer>> offers;    // per chunk of a bucket
  double width = 0;
};

SeedBucketPlan prepare_seed_buckets(const Adjacency& adj, const Mesh& m);

// label[v] = seed_label[k] of the seed whose path to v (edge lengths from m's
// positions) is shortest; -1 where no seed reaches. BadUsage as
// label_nearest_seeds_by_positions, for an unusable plan, or for a negative
// or non-finite seed distance.
void label_nearest_seeds_bucketed(const Adjacency& adj, const Mesh& m, const SeedBucketPlan& plan,
                                  std::span<const GrowSeed> seeds, std::span<const int32_t> seed_label,
                                  SeedBucketWorkspace& ws, std::span<int32_t> label);

}  // namespace locus
