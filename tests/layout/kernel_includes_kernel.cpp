// Layout probe, the control (ctest layout_downward_include_builds): the same
// kind of file including only its own floor and core compiles, so the failing
// probes fail because of the arrow and not because the probe build is broken.
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/mesh.hpp"
int locus_layout_probe_ok() { return 0; }
