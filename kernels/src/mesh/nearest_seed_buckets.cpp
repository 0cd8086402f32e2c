// Graph-geodesic Voronoi labels by a bucket queue
// (kernels/include/locus/kernels/mesh/nearest_seed_buckets.hpp; thesis §3.6).
#include "locus/kernels/mesh/nearest_seed_buckets.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <oneapi/tbb/parallel_for.h>

#include "locus/error.hpp"

namespace locus {

namespace {

void check_sizes(const Adjacency& adj, const Mesh& m) {
  if (adj.offsets.size() != static_cast<size_t>(m.num_vertices()) + 1)
    fail(ErrorCode::BadUsage, "seed labels: the adjacency belongs to another mesh");
}

using Offer = SeedBucketWorkspace::Offer;

// The offers of bucket b's vertices to their neighbors not yet taken (a
// shorter distance than the neighbor has), computed in parallel per chunk,
// then applied in b's order: every offer that is still shorter lowers the
// neighbor's distance, takes the label and queues it. Returns how many were
// queued. Offers land in later buckets only (w is below every edge).
int64_t relax_bucket(const Adjacency& adj, const Mesh& m, std::span<const int32_t> b, SeedBucketWorkspace& ws,
                     std::span<int32_t> label) {
  constexpr size_t kChunk = 256;
  const size_t chunks = (b.size() + kChunk - 1) / kChunk;
  if (ws.offers.size() < chunks) ws.offers.resize(chunks);
  const double* dist = ws.dist.data();
  const uint8_t* done = ws.done.data();
  auto offer = [&](size_t c) {
    HostVector<Offer>& out = ws.offers[c];
    out.clear();
    for (size_t i = c * kChunk; i < std::min(b.size(), (c + 1) * kChunk); ++i) {
      const int32_t q = b[i];
      for (int64_t a = adj.offsets[q]; a < adj.offsets[q + 1]; ++a) {
        const int32_t r = adj.neighbors[a];
        if (done[r]) continue;
        const double nd = dist[q] + adjacency_edge_length(m, q, r);
        if (nd < dist[r]) out.push_back({nd, r, q});
      }
    }
  };
  if (chunks > 1)
    tbb::parallel_for(size_t{0}, chunks, offer);
  else if (chunks == 1)
    offer(0);
  const size_t ring = ws.bucket.size();
  int64_t queued = 0;
  for (size_t c = 0; c < chunks; ++c)
    for (const Offer& o : ws.offers[c]) {
      if (!(o.distance < ws.dist[o.to])) continue;
      ws.dist[o.to] = o.distance;
      label[o.to] = label[o.from];
      ws.bucket[static_cast<size_t>(o.distance / ws.width) % ring].push_back(o.to);
      ++queued;
    }
  return queued;
}

}  // namespace

SeedBucketPlan prepare_seed_buckets(const Adjacency& adj, const Mesh& m) {
  check_sizes(adj, m);
  const int32_t n = m.num_vertices();
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (int32_t i = 0; i < n; ++i)
    for (int64_t a = adj.offsets[i]; a < adj.offsets[i + 1]; ++a)
      if (adj.neighbors[a] > i) {
        const double l = adjacency_edge_length(m, i, adj.neighbors[a]);
        lo = std::min(lo, l);
        hi = std::max(hi, l);
      }
  SeedBucketPlan p;
  if (hi == 0 && !(lo < std::numeric_limits<double>::infinity())) {  // no edges: the seeds alone
    p.width = 1;
    p.buckets = 3;
    return p;
  }
  if (!(lo > 0) || !std::isfinite(hi) || hi > kMaxBucketSpread * lo) return p;
  // Below the shortest edge by far more than rounding: a relaxation from
  // bucket k always lands in bucket k + 1 or later.
  p.width = lo * (1 - 1e-3);
  p.buckets = static_cast<int32_t>(hi / p.width) + 3;  // tentative distances span < hi + one width
  return p;
}

void label_nearest_seeds_bucketed(const Adjacency& adj, const Mesh& m, const SeedBucketPlan& plan,
                                  std::span<const GrowSeed> seeds, std::span<const int32_t> seed_label,
                                  SeedBucketWorkspace& ws, std::span<int32_t> label) {
  check_sizes(adj, m);
  const int32_t n = m.num_vertices();
  if (!plan.usable()) fail(ErrorCode::BadUsage, "seed labels: the bucket plan is not usable (check usable() first)");
  if (label.size() != static_cast<size_t>(n)) fail(ErrorCode::BadUsage, "seed labels: one label per vertex expected");
  if (seed_label.size() != seeds.size()) fail(ErrorCode::BadUsage, "seed labels: one label per seed expected");
  double far = 0;
  for (size_t k = 0; k < seeds.size(); ++k) {
    const GrowSeed& s = seeds[k];
    if (s.vertex < 0 || s.vertex >= n)
      fail(ErrorCode::BadUsage, "seed labels: seed " + std::to_string(k) + " is vertex " + std::to_string(s.vertex) +
                                    ", outside 0.." + std::to_string(n - 1));
    if (!(s.distance >= 0) || !std::isfinite(s.distance))
      fail(ErrorCode::BadUsage,
           "seed labels: seed " + std::to_string(k) + " has distance " + std::to_string(s.distance));
    far = std::max(far, s.distance);
  }
  const double w = plan.width;
  // Seeds farther than an edge (not a site's corners) widen the ring.
  const size_t ring = static_cast<size_t>(std::max<double>(plan.buckets, std::floor(far / w) + 3));
  ws.bucket.resize(ring);  // relax_bucket's ring too; the buckets are empty between calls
  ws.dist.assign(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  ws.done.assign(static_cast<size_t>(n), 0);
  std::fill(label.begin(), label.end(), -1);
  ws.width = w;
  double* dist = ws.dist.data();
  uint8_t* done = ws.done.data();
  const auto bucket_of = [w](double d) { return static_cast<int64_t>(d / w); };
  int64_t queued = 0, k = std::numeric_limits<int64_t>::max();
  for (size_t s = 0; s < seeds.size(); ++s) {  // an equal distance keeps the first seed's label
    const int32_t v = seeds[s].vertex;
    if (!(seeds[s].distance < dist[v])) continue;
    dist[v] = seeds[s].distance;
    label[v] = seed_label[s];
    ws.bucket[static_cast<size_t>(bucket_of(dist[v])) % ring].push_back(v);
    k = std::min(k, bucket_of(dist[v]));
    ++queued;
  }
  for (; queued > 0; ++k) {
    HostVector<int32_t>& b = ws.bucket[static_cast<size_t>(k) % ring];
    queued -= static_cast<int64_t>(b.size());
    // The bucket's vertices are final: taken all at once (repeats dropped,
    // queue order kept), their neighbors' offers computed in parallel, then
    // applied in queue order, as one vertex after another would.
    size_t live = 0;
    for (int32_t q : b)
      if (!done[q]) done[q] = 1, b[live++] = q;
    b.resize(live);
    queued += relax_bucket(adj, m, b, ws, label);
    b.clear();
  }
}

}  // namespace locus
