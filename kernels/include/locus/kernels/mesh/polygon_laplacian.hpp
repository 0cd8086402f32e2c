// The weighted polygon-edge Laplacian and its embedding system (thesis §2.2
// eq. 2.1, §2.3.1 eq. 2.4, §2.3.2 eq. 2.10).
//
// A Laplacian on a polygon mesh is one weight ω_e per unique edge of the faces
// (no diagonals of faces: §2.4, §2.7.3), acting as (L u)_i = Σ_j ω_ij (u_j - u_i).
// The embedding system of Algorithm 1 holds some vertices fixed (the boundary,
// or one pin per component of a closed mesh) and solves L V = b at the others.
// Moving the fixed vertices to the right-hand side leaves, on the free vertices,
//
//     K V_F = -b_F + Σ_{fixed j} ω_ij v_j,     K = D - W_FF   (D_ii = Σ_j ω_ij),
//
// which is symmetric positive definite whenever every component of the positive-
// weight graph touches a fixed vertex. K's pattern (free-free edges + diagonal)
// never changes, so it is ordered and analyzed ONCE (METIS + symbolic), and each
// new set of weights costs one numeric refactorization (DESIGN.md "Numeric core" 4).
//
// Weights that are exactly zero (Algorithm 1's steady state, §2.3.3) stay in the
// pattern as stored zeros. They would leave a vertex whose edges all vanish
// undetermined; unless the caller knows better (set_weight_floor_rel(0) when the
// positive weights tie every free vertex to a fixed one) the system therefore
// assembles max(ω_e, floor) with floor = weight_floor_rel · max_e ω_e, a spring so
// weak it only decides what the exact problem leaves open (such a vertex goes to
// the average of its neighbors) and keeps K positive definite.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

// Vertex positions as structure of arrays; in 2-D only c[0], c[1] are used.
using Coords = std::array<std::vector<double>, 3>;

struct EmbeddingSystemOptions {
  double weight_floor_rel = 1e-10;  // assembled weight >= this · max weight (see above)
  // Accept negative weights as they are (no floor), e.g. cotan weights for a
  // comparison; K may then be indefinite and factor() throws Numerical.
  bool allow_negative_weights = false;
};

// Scratch of EmbeddingSystem::solve, owned by the caller (sized on first use).
struct EmbeddingSolveWorkspace {
  std::vector<double> rhs8, work;
};

class EmbeddingSystem {
 public:
  // e0/e1: unique edges (any order, no duplicates, no self loops), fixed[v] != 0
  // for vertices whose position is prescribed. Orders and analyzes K's pattern.
  // Throws BadInput when an index is out of range or no vertex is free.
  EmbeddingSystem(int32_t nv, std::span<const int32_t> e0, std::span<const int32_t> e1,
                  std::span<const uint8_t> fixed, const EmbeddingSystemOptions& opt = {});

  int32_t num_vertices() const { return nv_; }
  int32_t num_free() const { return nfree_; }
  const std::vector<int32_t>& free_index() const { return free_index_; }  // -1 for fixed vertices
  const CscMatrix& matrix() const { return K_; }                        // K of the last factor()
  const SymbolicFactor& symbolic() const { return *sym_; }
  double order_s() const { return order_s_; }
  double analyze_s() const { return analyze_s_; }

  // Assembles K(ω) (weights per edge, >= 0, at least one > 0) and factors it:
  // the first call factorizes, later calls refactorize with the same symbolic
  // factor. Throws Numerical if K is not positive definite (a component without
  // a fixed vertex), BadInput for negative or non-finite weights.
  void factor(std::span<const double> weights, const RunContext& ctx = {});

  // Solves for `dims` (1..3) coordinates: out[k][v] = fixed_pos[k][v] at fixed
  // vertices, the solution of K V_F = -rhs_scale · b_F + Σ ω_ij v_j elsewhere.
  // `b` may hold empty vectors (zero right-hand side). Uses the weights of the
  // last factor(). Re-entrant: the scratch is the caller's `ws` (reused across
  // calls, one per thread) or, in the overload without it, local to the call;
  // both give the same result. Not concurrent with factor().
  void solve(int dims, const Coords& fixed_pos, const Coords& b, double rhs_scale, Coords& out,
             EmbeddingSolveWorkspace& ws) const;
  void solve(int dims, const Coords& fixed_pos, const Coords& b, double rhs_scale, Coords& out) const;

  // The floor of the next factor() calls (>= 0; 0 assembles the weights as given).
  void set_weight_floor_rel(double floor_rel);

  // The weights actually assembled by the last factor() (after the floor).
  const std::vector<double>& assembled_weights() const { return wa_; }

 private:
  int32_t nv_ = 0, nfree_ = 0;
  std::vector<int32_t> e0_, e1_;
  std::vector<int32_t> free_index_;
  // Per edge: value slots in K of the diagonals of its free endpoints and of the
  // off-diagonal entry (-1 where an endpoint is fixed).
  std::vector<int64_t> slot_a_, slot_b_, slot_off_;
  CscMatrix K_;
  std::shared_ptr<const SymbolicFactor> sym_;
  NumericFactor F_;
  bool factored_ = false;
  std::vector<double> wa_;
  EmbeddingSystemOptions opt_;
  double order_s_ = 0, analyze_s_ = 0;
};

// Applies the weighted Laplacian: out[k][i] = Σ_j ω_ij (p[k][j] - p[k][i]) for
// every vertex (eq. 2.1), straight from the edge list (an oracle independent of
// the factor, used to measure equilibrium residuals).
void apply_edge_laplacian(int32_t nv, std::span<const int32_t> e0, std::span<const int32_t> e1,
                          std::span<const double> weights, int dims, const Coords& p, Coords& out);

}  // namespace locus
