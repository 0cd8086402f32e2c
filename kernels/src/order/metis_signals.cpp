// What METIS' signal()/raise() were renamed to (cmake/metis.cmake).
//
// GKlib reports errors (failed allocations above all) with raise(SIGABRT or
// SIGTERM), and every METIS API call installs a handler for both, process-wide,
// that longjmps back into the call, and puts the previous handlers back at the
// end. That replaces the host's own handlers while METIS runs (a SIGTERM sent
// to the host meanwhile would longjmp on whatever thread received it), and two
// METIS calls at once (the two halves of a nested dissection) can restore in
// the wrong order and leave METIS' handler installed for good. Here signal()
// touches nothing, and raise() does synchronously what the handler would have
// done: the longjmp back to the METIS call that raised, which then returns its
// error status (METIS_ERROR_MEMORY, METIS_ERROR). Same results, no process state.
#include <csignal>
#include <cstdlib>

extern "C" {
// GKlib (error.c): the depth of the current thread's traps (-1: outside every
// METIS call) and the longjmp to the innermost one.
extern __thread int gk_cur_jbufs;
void gk_sigthrow(int signum);

__attribute__((visibility("hidden"))) void (*locus_metis_signal(int, void (*)(int)))(int) { return SIG_DFL; }

__attribute__((visibility("hidden"))) int locus_metis_raise(int signum) {
  if (gk_cur_jbufs >= 0) gk_sigthrow(signum);  // does not return
  std::abort();  // outside a METIS call (locus makes none): the default action, without the signal
}
}
