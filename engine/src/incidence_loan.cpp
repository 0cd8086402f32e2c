// The edge incidence set aside and rebuilt (incidence_loan.hpp; thesis §3.7.1).
#include "incidence_loan.hpp"

#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

IncidenceLoan::~IncidenceLoan() {
  try {
    restore();
  } catch (...) {  // out of memory while unwinding: the owner's incidence stays empty
  }
}

void IncidenceLoan::release() {
  if (released_) return;
  had_corners_ = !d_.incidence.edge_corner_offsets.empty();
  d_.incidence = EdgeIncidence{};
  released_ = true;
}

void IncidenceLoan::restore() {
  if (!released_) return;
  EdgeIncidence inc = edge_incidence(m_);
  if (!had_corners_) drop_edge_corners(inc);
  d_.incidence = std::move(inc);
  released_ = false;
}

}  // namespace locus
