// Nested dissection task tree (kernels/include/locus/kernels/order/nested_dissection.hpp).
//
// Each node owns its induced subgraph (and positions) and writes its part of
// the permutation: side 0 first, then side 1, then the separator. The parent's
// graph is released before the children run, so the tree never holds more
// than about twice the input graph. A separator larger than half its node
// (graphs with no small separators: a geometric cut of a non-mesh graph)
// means dissection does not pay there, and the node is ordered by AMD whole.
#include "locus/kernels/order/nested_dissection.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <bit>
#include <numeric>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/graph_coarsening.hpp"
#include "locus/kernels/order/level_separator.hpp"
#include "locus/kernels/order/metis_ordering.hpp"
#include "locus/kernels/order/minimum_degree.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"

namespace locus {

namespace {

struct Node {
  AdjacencyGraph g;
  HostVector<int32_t> global;  // original vertex of each local vertex
  HostVector<double> x, y, z;  // positions (empty without geometry)
  HostVector<int32_t> coarse;  // shared coarsening: coarse vertex of each local vertex (empty: none)
  int32_t nc = 0;               // coarse vertices of this node
  // The node's graph contracted along `coarse`, with edge multiplicities:
  // the root's from the coarsening itself, a child's taken from its
  // parent's (restrict_coarse), a node's own when it is large
  // (exact_min_vertices). Empty until separator() needs it.
  AdjacencyGraph cg;
  HostVector<int32_t> cew;
};

// Below this many vertices a node's two sides run in the same task: a task
// switch costs more than ordering a few hundred vertices.
constexpr int32_t kParallelMinVertices = 4000;
// Above this many vertices a node extracts its two sides' subgraphs at once.
constexpr int32_t kParallelExtractVertices = 50000;

class Dissector {
 public:
  Dissector(const AdjacencyGraph& root, const NestedDissectionOptions& opt, const RunContext& ctx, bool parallel)
      : root_(root),
        opt_(opt),
        ctx_(ctx),
        parallel_(parallel),
        ticker_(ctx, "ordering", root.n()),
        index_([n = root.n()] { return HostVector<int32_t>(static_cast<size_t>(n), -1); }) {}

  ProgressTicker& ticker() const { return ticker_; }

  // Progress: vertices placed (in leaves and separators) of the root's.
  void order(Node node, int32_t* out) const {
    ctx_.check_cancel();
    ticker_.tick();
    const int32_t m = static_cast<int32_t>(node.global.size());
    if (m <= opt_.leaf_size) return leaf_done(node, out);
    HostVector<int8_t> part;
    separator(node, part);
    const int32_t nsep = static_cast<int32_t>(std::count(part.begin(), part.end(), int8_t{2}));
    const int32_t nside0 = static_cast<int32_t>(std::count(part.begin(), part.end(), int8_t{0}));
    // No separator worth the name (graphs with no small separators), or no
    // progress (an edgeless graph comes back whole on one side): AMD whole.
    if (2 * nsep > m || (nsep == 0 && (nside0 == 0 || nside0 == m))) return leaf_done(node, out);
    ticker_.add(nsep);
    Node child[2];
    const int32_t side_size[2] = {nside0, m - nsep - nside0};
    const auto extract = [&](int8_t s) {
      poll();
      if (opt_.halo && side_size[s] <= opt_.leaf_size) {
        // A leaf with its halo reads the root's graph (leaf()): its vertex
        // list is all it needs.
        for (int32_t v = 0; v < m; ++v)
          if (part[v] == s) child[s].global.push_back(node.global[v]);
        return;
      }
      child[s].g = induced_subgraph(node.g, part, s, child[s].global);
      if (!node.x.empty()) {
        const auto gather = [&ids = child[s].global](const HostVector<double>& from, HostVector<double>& to) {
          to.resize(ids.size());
          for (size_t k = 0; k < ids.size(); ++k) to[k] = from[ids[k]];
        };
        gather(node.x, child[s].x);
        gather(node.y, child[s].y);
        gather(node.z, child[s].z);
      }
      if (!node.coarse.empty() && child[s].g.n() >= opt_.coarse_min_vertices) restrict_coarse(node, child[s]);
      for (int32_t& v : child[s].global) v = node.global[v];
    };
    // The two sides' subgraphs are independent: at the top levels, where
    // the other thread would otherwise wait for this node, both at once.
    if (parallel_ && m >= kParallelExtractVertices)
      tbb::parallel_invoke([&] { extract(0); }, [&] { extract(1); });
    else {
      extract(0);
      extract(1);
    }
    const int32_t n0 = side_size[0], n1 = side_size[1];
    int32_t* sep_out = out + n0 + n1;
    for (int32_t v = 0; v < m; ++v)
      if (part[v] == 2) *sep_out++ = node.global[v];
    node = Node{};  // release before recursing
    part = {};
    if (parallel_ && std::min(n0, n1) >= kParallelMinVertices)
      tbb::parallel_invoke([&] { order(std::move(child[0]), out); },
                           [&] { order(std::move(child[1]), out + n0); });
    else {
      order(std::move(child[0]), out);
      order(std::move(child[1]), out + n0);
    }
  }

 private:
  // Between the passes over a node's graph (10-40 ms each at the top levels of
  // a 416k mesh): a report, the C host's chance to cancel, and the flag.
  void poll() const {
    ticker_.tick();
    ctx_.check_cancel();
  }

  void separator(Node& node, HostVector<int8_t>& part) const {
    const int32_t m = node.g.n();
    if (!node.coarse.empty() && m >= opt_.coarse_min_vertices) {
      // METIS on the node's contraction along the shared coarsening, then
      // the projected (about two vertices thick) separator refined here.
      // METIS gets the coarse edges' multiplicities: with every edge
      // weighing 1 its heavy-edge matching of the contraction is blind
      // (separators ~3% longer, docs/ordering.md). A large node contracts its
      // own graph; a smaller one got its contraction from its parent.
      HostVector<int32_t> vwgt;
      if (node.cg.n() != node.nc || m >= opt_.exact_min_vertices) {
        node.cg = contract_graph(node.g, node.coarse, node.nc, vwgt, &node.cew);
      } else {
        vwgt.assign(static_cast<size_t>(node.nc), 0);
        for (const int32_t c : node.coarse) ++vwgt[c];
      }
      poll();
      HostVector<int8_t> coarse_part;
      if (node.cg.n() < opt_.level_separator_below && level_separator(node.cg, vwgt, coarse_part)) {
        project_and_refine(node, coarse_part, part);
      } else if (const int tries = tries_at(m); tries <= 1) {
        metis_on_contraction(node, vwgt, opt_.metis_seed, part);
      } else {
        best_of_tries(node, vwgt, tries, part);
      }
      poll();
    } else if (opt_.separator == NestedDissectionOptions::Separator::Geometric) {
      // A plane cut is jagged where it crosses the mesh's edges: the same FM
      // passes as METIS' projected separators get shorten it (at 104k the
      // fill went from 1.16x METIS_NodeND's to 1.00x, docs/ordering.md).
      geometric_separator(node.g, node.x, node.y, node.z, opt_.geometric, part);
      refine(node, part);
    } else {
      metis_vertex_separator(node.g, opt_.metis_seed, part, &ticker_);  // polls the cancel flag inside METIS
    }
  }

  // METIS' separator of the node's contraction (seed `seed`), projected and
  // refined; returns its size.
  int32_t metis_on_contraction(const Node& node, const HostVector<int32_t>& vwgt, int seed,
                               HostVector<int8_t>& part) const {
    HostVector<int8_t> coarse_part;
    metis_vertex_separator(node.cg, seed, coarse_part, &ticker_, vwgt,
                           opt_.metis_edge_weights ? std::span<const int32_t>(node.cew) : std::span<const int32_t>());
    poll();
    return project_and_refine(node, coarse_part, part);
  }

  // The coarse separator on the node's vertices, refined; returns its size.
  int32_t project_and_refine(const Node& node, const HostVector<int8_t>& coarse_part, HostVector<int8_t>& part) const {
    const int32_t m = node.g.n();
    part.resize(static_cast<size_t>(m));
    for (int32_t v = 0; v < m; ++v) part[v] = coarse_part[node.coarse[v]];
    return refine(node, part);
  }

  // FM passes on a separator of the node's graph, with this thread's
  // workspace; returns its size.
  int32_t refine(const Node& node, HostVector<int8_t>& part) const {
    return refine_vertex_separator(node.g, part, opt_.refinement, &refine_ws_.local());
  }

  // Separators to try at a node of m vertices: separator_tries from
  // tries_full_vertices up, half as many for every halving of m below
  // (nested_dissection.hpp), at least one.
  int tries_at(int32_t m) const {
    const int64_t most = std::max(1, opt_.separator_tries);
    const int64_t scaled = most * m / std::max(1, opt_.tries_full_vertices);
    return static_cast<int>(std::bit_floor(static_cast<uint64_t>(std::clamp<int64_t>(scaled, 1, most))));
  }

  // The smallest of `tries` refined separators (METIS seeds metis_seed + k;
  // ties: the lowest k), tried in parallel. The top separators lie on every
  // local solve's path (docs/ordering.md), and at the top of the tree the
  // other threads would wait anyway.
  void best_of_tries(const Node& node, const HostVector<int32_t>& vwgt, int tries, HostVector<int8_t>& part) const {
    std::vector<HostVector<int8_t>> parts(static_cast<size_t>(tries));
    std::vector<int32_t> sizes(static_cast<size_t>(tries));
    const auto one = [&](int k) { sizes[k] = metis_on_contraction(node, vwgt, opt_.metis_seed + k, parts[k]); };
    if (parallel_) {
      tbb::parallel_for(0, tries, one);
    } else {
      for (int k = 0; k < tries; ++k) one(k);
    }
    const auto best = std::min_element(sizes.begin(), sizes.end()) - sizes.begin();  // the first of the smallest
    part = std::move(parts[best]);
  }

  // The child's coarse vertices: the parent's that have a vertex in it, renumbered.
  static void restrict_coarse(const Node& parent, Node& child) {
    HostVector<int32_t> id(static_cast<size_t>(parent.nc), -1);
    child.coarse.resize(child.global.size());
    int32_t nc = 0;
    for (size_t k = 0; k < child.global.size(); ++k) {  // child.global: parent-local indices here
      int32_t& c = id[parent.coarse[child.global[k]]];
      if (c < 0) c = nc++;
      child.coarse[k] = c;
    }
    child.nc = nc;
    if (parent.cg.n() == parent.nc)  // the parent's contraction, restricted (graph_coarsening.hpp)
      child.cg = restrict_contraction(parent.cg, id, nc, parent.cew, &child.cew);
  }

  void leaf_done(const Node& node, int32_t* out) const {
    leaf(node, out);
    ticker_.add(static_cast<double>(node.global.size()));
  }

  void leaf(const Node& node, int32_t* out) const {
    if (!opt_.halo || node.global.size() == static_cast<size_t>(root_.n())) {
      const HostVector<int32_t> p = minimum_degree_order(node.g);
      for (size_t k = 0; k < p.size(); ++k) out[k] = node.global[p[k]];
      return;
    }
    // The leaf plus its halo: root-graph neighbors outside the leaf (all in
    // separators above it, never in another leaf). The thread's own index
    // array maps root vertices to the leaf-plus-halo numbering: a halo vertex
    // borders other leaves, which other threads may be building at the same
    // moment, so one shared array would race; a per-thread one also spares
    // the binary searches in the leaf's and the halo's lists.
    const HostVector<int32_t>& ids = node.global;  // ascending
    const int32_t m = static_cast<int32_t>(ids.size());
    HostVector<int32_t>& index = index_.local();
    for (int32_t k = 0; k < m; ++k) index[ids[k]] = k;
    HostVector<int32_t> halo;
    for (const int32_t v : ids)
      for (int32_t p = root_.xadj[v]; p < root_.xadj[v + 1]; ++p)
        if (index[root_.adj[p]] < 0) halo.push_back(root_.adj[p]);
    std::sort(halo.begin(), halo.end());
    halo.erase(std::unique(halo.begin(), halo.end()), halo.end());
    const int32_t nh = m + static_cast<int32_t>(halo.size());
    for (int32_t k = m; k < nh; ++k) index[halo[k - m]] = k;
    // Rows come out sorted without a sort: the root's lists are ascending,
    // and so are the leaf's local indices (< m) and the halo's (>= m) taken
    // apart, so a row is its leaf entries in order, then its halo entries.
    AdjacencyGraph h;
    h.xadj.assign(1, 0);
    HostVector<int32_t> row_halo;
    for (int32_t k = 0; k < nh; ++k) {
      const int32_t v = k < m ? ids[k] : halo[k - m];
      row_halo.clear();
      for (int32_t p = root_.xadj[v]; p < root_.xadj[v + 1]; ++p) {
        const int32_t l = index[root_.adj[p]];
        if (l >= m) row_halo.push_back(l);
        else if (l >= 0) h.adj.push_back(l);
      }
      h.adj.insert(h.adj.end(), row_halo.begin(), row_halo.end());
      h.xadj.push_back(static_cast<int32_t>(h.adj.size()));
    }
    for (const int32_t v : ids) index[v] = -1;
    for (const int32_t v : halo) index[v] = -1;
    HostVector<int32_t> constraint(nh, 0);
    std::fill(constraint.begin() + m, constraint.end(), 1);
    const HostVector<int32_t> p = constrained_minimum_degree_order(h, constraint);
    int32_t k = 0;
    for (const int32_t v : p)
      if (v < m) out[k++] = ids[v];
  }

  const AdjacencyGraph& root_;
  const NestedDissectionOptions& opt_;
  const RunContext& ctx_;
  bool parallel_;
  mutable ProgressTicker ticker_;
  // leaf(): per thread, each root vertex's index in the leaf being built (its
  // own vertices, then its halo), else -1.
  mutable tbb::enumerable_thread_specific<HostVector<int32_t>> index_;
  // refine(): per thread (a refinement never waits on other tasks).
  mutable tbb::enumerable_thread_specific<SeparatorRefinementWorkspace> refine_ws_;
};

}  // namespace

HostVector<int32_t> nested_dissection(const AdjacencyGraph& g, std::span<const double> x, std::span<const double> y,
                                       std::span<const double> z, const NestedDissectionOptions& opt,
                                       const RunContext& ctx) {
  const int32_t n = g.n();
  HostVector<int32_t> perm(static_cast<size_t>(n));
  Node root;
  root.g = g;
  root.global.resize(n);
  std::iota(root.global.begin(), root.global.end(), 0);
  if (opt.separator == NestedDissectionOptions::Separator::Geometric) {
    root.x.assign(x.begin(), x.end());
    root.y.assign(y.begin(), y.end());
    root.z.assign(z.begin(), z.end());
  }
  const bool parallel = ctx.threads != 1;
  const Dissector d(g, opt, ctx, parallel);
  run_with_threads(ctx.threads, [&] {  // the coarsening's contractions run in parallel blocks too
    if (opt.coarse_levels > 0 && n >= opt.coarse_min_vertices &&
        opt.separator == NestedDissectionOptions::Separator::Metis) {
      // The root's contraction comes with the map (graph_coarsening.hpp).
      Contraction top;
      root.nc = coarsening_map(g, opt.coarse_levels, root.coarse, &d.ticker(), &top);
      root.cg = std::move(top.graph);
      root.cew = std::move(top.ewgt);
    }
    d.order(std::move(root), perm.data());
  });
  return perm;
}

}  // namespace locus
