// Cancel points in serial kernels (kernels/include/locus/kernels/parallel/cancel_point.hpp).
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {
thread_local CancelScope* t_scope = nullptr;
}  // namespace

CancelScope::CancelScope(ProgressTicker& ticker) : ticker_(&ticker), outer_(t_scope) { t_scope = this; }
CancelScope::~CancelScope() { t_scope = outer_; }

void cancel_point_poll() {
  CancelScope* s = t_scope;
  if (!s) return;
  s->ticker_->tick();
  s->ticker_->context().check_cancel();
}

}  // namespace locus
