/* METIS_ComputeVertexSeparator inside GKlib's error trap (compiled with METIS:
 * cmake/metis.cmake). Unlike METIS_NodeND, that entry point sets no trap of its
 * own: a failed allocation inside it (the host's allocator out of memory, or a
 * cancel: kernels/include/locus/kernels/order/metis_call.hpp) would reach
 * raise() outside any METIS call, and its memory would be lost. Here, as
 * METIS_NodeND does, the allocations are recorded, the error longjmps back,
 * everything allocated in the call is freed and the error is returned. */
#include "metislib.h"

static int separator_single_run(idx_t* nvtxs, idx_t* xadj, idx_t* adjncy, idx_t* vwgt, idx_t* options,
                                idx_t* sepsize, idx_t* part, int niparts) {
  ctrl_t* ctrl = SetupCtrl(METIS_OP_OMETIS, options, 1, 3, NULL, NULL);
  if (ctrl == NULL) return METIS_ERROR_INPUT;
  InitRandom(ctrl->seed);
  graph_t* graph = SetupGraph(ctrl, *nvtxs, 1, xadj, adjncy, vwgt, NULL, NULL);
  AllocateWorkSpace(ctrl, graph);
  MlevelNodeBisectionL1(ctrl, graph, niparts);
  *sepsize = graph->pwgts[2];
  icopy(*nvtxs, graph->where, part);
  FreeGraph(&graph);
  FreeCtrl(&ctrl);
  return METIS_OK;
}

int locus_metis_vertex_separator(idx_t* nvtxs, idx_t* xadj, idx_t* adjncy, idx_t* vwgt, idx_t* options,
                                 idx_t* sepsize, idx_t* part, int single_run) {
  int sigrval = 0;
  volatile int rc = METIS_OK;
  if (!gk_malloc_init()) return METIS_ERROR_MEMORY;
  gk_sigtrap();
  if ((sigrval = gk_sigcatch()) != 0) goto SIGTHROW;
  if (single_run == 0) {
    rc = METIS_ComputeVertexSeparator(nvtxs, xadj, adjncy, vwgt, options, sepsize, part);
  } else {
    rc = separator_single_run(nvtxs, xadj, adjncy, vwgt, options, sepsize, part, single_run);
  }
SIGTHROW:
  gk_siguntrap();
  gk_malloc_cleanup(0);
  return sigrval != 0 ? metis_rcode(sigrval) : rc;
}
