// libFuzzer target for the asset formats read through assimp
// (io/src/read_assimp.cpp, flatten_scene.cpp, weld_vertices.cpp) by
// read_mesh_from_memory. The first byte picks the format (its value modulo
// the list below), the rest is the file; seeds are in tests/fuzz_corpus/assimp/.
// The only acceptable outcomes are a Mesh or a locus::Error; any other
// exception escapes and counts as a finding, as do crashes, sanitizer reports
// (in locus's code: the system assimp is not instrumented), hangs (-timeout)
// and memory blow-ups (-rss_limit_mb). Every other read alternates welding,
// so both paths of the flattening run. Run with tools/run_fuzzers.sh.
#include <cstddef>
#include <cstdint>

#include "locus/error.hpp"
#include "locus/mesh_io.hpp"

namespace {
// 0 glb, 1 gltf, 2 stl, 3 dae, 4 fbx, 5 3mf, 6 3ds, 7 x, 8 ac, 9 lwo, 10 ms3d, 11 md2, 12 blend, 13 dxf, 14 ase, 15 ifc
const char* const kFormats[] = {"glb", "gltf", "stl", "dae", "fbx", "3mf", "3ds", "x",
                                "ac",  "lwo",  "ms3d", "md2", "blend", "dxf", "ase", "ifc"};
constexpr size_t kCount = sizeof(kFormats) / sizeof(kFormats[0]);
}  // namespace

// assimp 5.2.5 leaks on some of its own error paths (truncated DirectX and
// ASCII STL files: the allocations and frees are all inside libassimp). Those
// are not locus's to fix and would stop every run at the first truncated
// seed; leaks in locus's code are still reported.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const char* fmt = kFormats[data[0] % kCount];
  locus::ReadOptions opt;
  opt.max_bytes = uint64_t(512) << 20;  // keep allocations well under -rss_limit_mb
  opt.weld = (data[0] / kCount) % 2 == 0;
  try {
    locus::MeshAttributes attr;
    const locus::Mesh m = locus::read_mesh_from_memory(reinterpret_cast<const char*>(data + 1), size - 1, fmt,
                                                       std::string("fuzz.") + fmt, opt, &attr);
    // Touch the result so that an inconsistent mesh or map shows up under ASan.
    volatile int64_t sum = 0;
    for (int32_t f = 0; f < m.num_faces(); ++f)
      for (int32_t v : m.face(f)) sum = sum + static_cast<int64_t>(m.x.at(static_cast<size_t>(v)) != 0);
    for (int32_t w : attr.asset_report.file_to_vertex) sum = sum + static_cast<int64_t>(m.y.at(static_cast<size_t>(w)) != 0);
  } catch (const locus::Error&) {
  }
  return 0;
}
