/* METIS_ComputeVertexSeparator inside GKlib's error trap (compiled with METIS:
 * cmake/metis.cmake). Unlike METIS_NodeND, that entry point sets no trap of its
 * own: a failed allocation inside it (the host's allocator out of memory, or a
 * cancel: kernels/include/locus/kernels/order/metis_call.hpp) would reach
 * raise() outside any METIS call, and its memory would be lost. Here, as
 * METIS_NodeND does, the allocations are recorded, the error longjmps back,
 * everything allocated in the call is freed and the error is returned. */
#include "metislib.h"

int locus_metis_vertex_separator(idx_t* nvtxs, idx_t* xadj, idx_t* adjncy, idx_t* vwgt, idx_t* options,
                                 idx_t* sepsize, idx_t* part) {
  int sigrval = 0;
  volatile int rc = METIS_OK;
  if (!gk_malloc_init()) return METIS_ERROR_MEMORY;
  gk_sigtrap();
  if ((sigrval = gk_sigcatch()) != 0) goto SIGTHROW;
  rc = METIS_ComputeVertexSeparator(nvtxs, xadj, adjncy, vwgt, options, sepsize, part);
SIGTHROW:
  gk_siguntrap();
  gk_malloc_cleanup(0);
  return sigrval != 0 ? metis_rcode(sigrval) : rc;
}
