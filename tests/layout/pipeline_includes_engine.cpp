// Layout probe (ctest layout_upward_include_fails): a pipelines-floor file that
// includes the engine's Session. Must fail to compile against locus_pipelines.
#include "locus/session.hpp"
int locus_layout_probe_engine() { return 0; }
