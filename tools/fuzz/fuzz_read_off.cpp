// libFuzzer target for the OFF reader (io/src/read_off.cpp) through
// read_mesh_from_memory. The only acceptable outcomes are a Mesh or a
// locus::Error; any other exception escapes and counts as a finding, as do
// crashes, sanitizer reports, hangs (-timeout) and memory blow-ups (-rss_limit_mb).
// Run with tools/run_fuzzers.sh.
#include <cstddef>
#include <cstdint>

#include "locus/error.hpp"
#include "locus/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  locus::ReadOptions opt;
  opt.max_bytes = uint64_t(512) << 20;  // keep header-driven allocations well under -rss_limit_mb
  try {
    const locus::Mesh m = locus::read_mesh_from_memory(reinterpret_cast<const char*>(data), size, "off", "fuzz.off", opt);
    // Touch the result so that an inconsistent mesh shows up under ASan.
    volatile int64_t sum = 0;
    for (int32_t f = 0; f < m.num_faces(); ++f)
      for (int32_t v : m.face(f)) sum = sum + static_cast<int64_t>(m.x.at(static_cast<size_t>(v)) != 0);
  } catch (const locus::Error&) {
  }
  return 0;
}
