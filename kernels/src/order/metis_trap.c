/* METIS_ComputeVertexSeparator inside GKlib's error trap (compiled with METIS:
 * cmake/metis.cmake). Unlike METIS_NodeND, that entry point sets no trap of its
 * own: a failed allocation inside it (the host's allocator out of memory, or a
 * cancel: kernels/include/locus/kernels/order/metis_call.hpp) would reach
 * raise() outside any METIS call, and its memory would be lost. Here, as
 * METIS_NodeND does, the allocations are recorded, the error longjmps back,
 * everything allocated in the call is freed and the error is returned. */
#include "metislib.h"

/* METIS_ComputeVertexSeparator's work with edge weights as well: its public
 * entry point takes vertex weights only, so a contracted graph's edges would
 * all weigh 1 and METIS' heavy-edge matching would lose which coarse vertices
 * are joined by many fine edges. Same steps, through METIS' own functions. */
static int vertex_separator_weighted(idx_t* nvtxs, idx_t* xadj, idx_t* adjncy, idx_t* vwgt, idx_t* adjwgt,
                                     idx_t* options, idx_t* sepsize, idx_t* part) {
  ctrl_t* ctrl = SetupCtrl(METIS_OP_OMETIS, options, 1, 3, NULL, NULL);
  if (ctrl == NULL) return METIS_ERROR_INPUT;
  InitRandom(ctrl->seed);
  graph_t* graph = SetupGraph(ctrl, *nvtxs, 1, xadj, adjncy, vwgt, NULL, adjwgt);
  AllocateWorkSpace(ctrl, graph);
  ctrl->CoarsenTo = 100;
  MlevelNodeBisectionMultiple(ctrl, graph);
  *sepsize = graph->pwgts[2];
  icopy(*nvtxs, graph->where, part);
  FreeGraph(&graph);
  FreeCtrl(&ctrl);
  return METIS_OK;
}

int locus_metis_vertex_separator(idx_t* nvtxs, idx_t* xadj, idx_t* adjncy, idx_t* vwgt, idx_t* adjwgt,
                                 idx_t* options, idx_t* sepsize, idx_t* part) {
  int sigrval = 0;
  volatile int rc = METIS_OK;
  if (!gk_malloc_init()) return METIS_ERROR_MEMORY;
  gk_sigtrap();
  if ((sigrval = gk_sigcatch()) != 0) goto SIGTHROW;
  rc = adjwgt ? vertex_separator_weighted(nvtxs, xadj, adjncy, vwgt, adjwgt, options, sepsize, part)
              : METIS_ComputeVertexSeparator(nvtxs, xadj, adjncy, vwgt, options, sepsize, part);
SIGTHROW:
  gk_siguntrap();
  gk_malloc_cleanup(0);
  return sigrval != 0 ? metis_rcode(sigrval) : rc;
}
