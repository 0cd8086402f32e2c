// doctest entry point for the locus test suite.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

// Under LeakSanitizer (the ASan build of .ci/run): assimp 5.2.5 leaks on some
// of its own error paths (truncated DirectX and ASCII STL files), which the
// hostile-file tests of tests/io/read_assimp.cpp take on purpose. Leaks of
// locus' own code are still reported. Unused in other builds. The hook must be
// exported (the tests build with -fvisibility=hidden), or the runtime never sees it.
extern "C" __attribute__((visibility("default"), used)) const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }
