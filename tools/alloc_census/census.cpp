// Allocation census (docs/shipping.md "The host's allocator"):
// every malloc/calloc/realloc/aligned allocation of 64 KB or more during the
// first geodesic, a log map and a CVT through the C API, split into those made
// by the host allocator's callbacks (routed) and the others, listed by call
// stack (resolve with addr2line -f -C -e census ADDRESS: built without PIE).
// A stand-alone program against the installed package: it replaces malloc for
// its whole process, which is why it is not part of locus-tests or locus-bench.
//
//   cmake --install build --prefix P
//   cmake -S tools/alloc_census -B /tmp/census -DCMAKE_PREFIX_PATH=P && cmake --build /tmp/census
//   /tmp/census/census cache/meshes/armadillo.off [SUBDIVIDE]
//
// SUBDIVIDE (default 0): 1:4 midpoint subdivisions before the session is made
// (2 on armadillo: 416k vertices, where the ordering is nested dissection).
#include <execinfo.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <malloc.h>

#include <algorithm>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include <locus/locus.h>
#include <locus/mesh_io.hpp>
#include <locus/session.hpp>

extern "C" void* __libc_malloc(size_t);
extern "C" void* __libc_calloc(size_t, size_t);
extern "C" void* __libc_realloc(void*, size_t);
extern "C" void __libc_free(void*);
extern "C" void* __libc_memalign(size_t, size_t);

namespace {
std::atomic<bool> g_on{false};
thread_local bool t_in = false;  // inside the host callback or the census itself
std::atomic<long> g_routed_n{0}, g_routed_b{0}, g_other_n{0}, g_other_b{0}, g_mmap_n{0}, g_mmap_b{0};

struct Site { long n = 0, bytes = 0; };
std::mutex g_mu;
std::map<std::string, Site>* g_sites = nullptr;

void record(size_t n, bool mapped = false) {
  if (!g_on.load(std::memory_order_relaxed) || n < 65536 || t_in) return;
  t_in = true;
  (mapped ? g_mmap_n : g_other_n)++;
  (mapped ? g_mmap_b : g_other_b) += static_cast<long>(n);
  void* bt[12];
  const int k = backtrace(bt, 12);
  if (mapped) backtrace_symbols_fd(bt, k, 2);  // a library's own mapping: which library (stderr)
  std::string key = mapped ? "mmap " : "";
  char buf[32];
  for (int i = 2; i < k && i < 9; ++i) {
    std::snprintf(buf, sizeof buf, "%p ", bt[i]);
    key += buf;
  }
  {
    std::lock_guard<std::mutex> lock(g_mu);
    if (!g_sites) g_sites = new std::map<std::string, Site>;
    Site& s = (*g_sites)[key];
    s.n++;
    s.bytes += static_cast<long>(n);
  }
  t_in = false;
}
}  // namespace

extern "C" void* malloc(size_t n) { record(n); return __libc_malloc(n); }
extern "C" void* calloc(size_t a, size_t b) { record(a * b); return __libc_calloc(a, b); }
extern "C" void* realloc(void* p, size_t n) { record(n); return __libc_realloc(p, n); }
extern "C" void free(void* p) { __libc_free(p); }
// Memory a library maps itself (OpenBLAS' buffers, oneTBB's scalable allocator):
// the C library's malloc maps through its internal entry, not this one.
extern "C" void* mmap(void* a, size_t n, int prot, int flags, int fd, off_t off) {
  if (!(flags & MAP_FIXED) && fd < 0) record(n, true);
  return reinterpret_cast<void*>(syscall(SYS_mmap, a, n, prot, flags, fd, off));
}
extern "C" void* memalign(size_t a, size_t n) { record(n); return __libc_memalign(a, n); }
extern "C" void* aligned_alloc(size_t a, size_t n) { record(n); return __libc_memalign(a, n); }
extern "C" int posix_memalign(void** p, size_t a, size_t n) { record(n); *p = __libc_memalign(a, n); return *p ? 0 : 12; }

static void* host_alloc(size_t n, void*) {
  t_in = true;
  void* p = __libc_malloc(n);
  t_in = false;
  if (g_on && n >= 65536) { g_routed_n++; g_routed_b += static_cast<long>(n); }
  return p;
}
static void host_free(void* p, void*) { __libc_free(p); }

// xyz (3 nv) and triangles (3 nf), subdivided 1:4 at edge midpoints.
static void subdivide(std::vector<double>& xyz, std::vector<int32_t>& tri) {
  std::unordered_map<uint64_t, int32_t> mid;
  auto midpoint = [&](int32_t a, int32_t b) {
    const uint64_t key = (uint64_t(std::min(a, b)) << 32) | uint32_t(std::max(a, b));
    auto [it, fresh] = mid.emplace(key, int32_t(xyz.size() / 3));
    if (fresh)
      for (int c = 0; c < 3; ++c) xyz.push_back(0.5 * (xyz[3 * size_t(a) + c] + xyz[3 * size_t(b) + c]));
    return it->second;
  };
  std::vector<int32_t> out;
  for (size_t f = 0; f + 2 < tri.size(); f += 3) {
    const int32_t a = tri[f], b = tri[f + 1], c = tri[f + 2];
    const int32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    out.insert(out.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
  }
  tri.swap(out);
}

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  locus_set_allocator(host_alloc, host_free, nullptr);
  const int times = argc > 2 ? std::atoi(argv[2]) : 0;
  std::vector<double> xyz;
  std::vector<int32_t> tri;
  try {
    const locus::Mesh m = locus::read_mesh(argv[1]);
    for (int32_t v = 0; v < m.num_vertices(); ++v) xyz.insert(xyz.end(), {m.x[v], m.y[v], m.z[v]});
    tri.assign(m.face_vertices.begin(), m.face_vertices.end());  // a triangle mesh
  } catch (const std::exception& e) {
    std::puts(e.what());
    return 1;
  }
  for (int k = 0; k < times; ++k) subdivide(xyz, tri);
  locus_session* s = nullptr;
  if (locus_session_create(xyz.data(), int64_t(xyz.size() / 3), tri.data(), int64_t(tri.size() / 3), &s) != LOCUS_OK) {
    std::puts(locus_last_error_message());
    return 1;
  }
  {
    std::printf("subdivided %d times: %lld vertices\n", times, static_cast<long long>(xyz.size() / 3));
  }
  const int64_t n = locus_session_vertex_count(s);
  std::vector<double> d(n), uv(2 * n);
  std::vector<int32_t> labels(n);
  const char* names[3] = {"geodesic", "logmap", "cvt"};
  for (int call = 0; call < 3; ++call) {
    g_routed_n = g_routed_b = g_other_n = g_other_b = g_mmap_n = g_mmap_b = 0;
    if (g_sites) g_sites->clear();
    g_on = true;
    locus_status st = call == 0 ? locus_geodesic_distance(s, 0, d.data())
                      : call == 1 ? locus_logmap(s, 7, 0.1, uv.data())
                                  : locus_cvt(s, 500, 3, 1, labels.data());
    g_on = false;
    std::printf("%s: status %d; >=64KB routed %ld blocks %.1f MB; not routed %ld blocks %.1f MB (%.1f%% of bytes routed); "
                "anonymous mmap by libraries %ld, %.1f MB\n",
                names[call], st, g_routed_n.load(), g_routed_b / 1e6, g_other_n.load(), g_other_b / 1e6,
                100.0 * g_routed_b / std::max(1L, g_routed_b.load() + g_other_b.load()), g_mmap_n.load(), g_mmap_b / 1e6);
    std::vector<std::pair<long, std::string>> top;
    if (g_sites) for (auto& [k, v] : *g_sites) top.push_back({v.bytes, k + " n=" + std::to_string(v.n)});
    std::sort(top.rbegin(), top.rend());
    for (size_t i = 0; i < top.size(); ++i) std::printf("SITE %.1f MB %s\n", top[i].first / 1e6, top[i].second.c_str());
  }
  std::vector<std::pair<long, std::string>> top;
  if (g_sites) for (auto& [k, v] : *g_sites) top.push_back({v.bytes, k + " n=" + std::to_string(v.n)});
  std::sort(top.rbegin(), top.rend());
  for (size_t i = 0; i < top.size() && i < 25; ++i) std::printf("SITE %.1f MB %s\n", top[i].first / 1e6, top[i].second.c_str());
  locus_session_destroy(s);
  return 0;
}
