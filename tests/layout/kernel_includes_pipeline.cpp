// Layout probe (ctest layout_upward_include_fails): a kernels-floor file that
// includes a pipeline header. Built against locus_kernels' include path only,
// it must fail to compile: the floors' include paths enforce the arrows.
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
int locus_layout_probe_upward() { return 0; }
