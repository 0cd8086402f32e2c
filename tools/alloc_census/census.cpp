// Allocation census (issue 24 item 2; docs/shipping.md "The host's allocator"):
// every malloc/calloc/realloc/aligned allocation of 64 KB or more during the
// first geodesic, a log map and a CVT through the C API, split into those made
// by the host allocator's callbacks (routed) and the others, listed by call
// stack (resolve with addr2line -f -C -e census ADDRESS: built without PIE).
// A stand-alone program against the installed package: it replaces malloc for
// its whole process, which is why it is not part of locus-tests or locus-bench.
//
//   cmake --install build --prefix P
//   cmake -S tools/alloc_census -B /tmp/census -DCMAKE_PREFIX_PATH=P && cmake --build /tmp/census
//   /tmp/census/census cache/meshes/armadillo.off
#include <execinfo.h>
#include <malloc.h>

#include <algorithm>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <locus/locus.h>
#include <locus/session.hpp>

extern "C" void* __libc_malloc(size_t);
extern "C" void* __libc_calloc(size_t, size_t);
extern "C" void* __libc_realloc(void*, size_t);
extern "C" void __libc_free(void*);
extern "C" void* __libc_memalign(size_t, size_t);

namespace {
std::atomic<bool> g_on{false};
thread_local bool t_in = false;  // inside the host callback or the census itself
std::atomic<long> g_routed_n{0}, g_routed_b{0}, g_other_n{0}, g_other_b{0};
struct Site { long n = 0, bytes = 0; };
std::mutex g_mu;
std::map<std::string, Site>* g_sites = nullptr;

void record(size_t n) {
  if (!g_on.load(std::memory_order_relaxed) || n < 65536 || t_in) return;
  t_in = true;
  g_other_n++;
  g_other_b += static_cast<long>(n);
  void* bt[12];
  const int k = backtrace(bt, 12);
  std::string key;
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

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  locus_set_allocator(host_alloc, host_free, nullptr);
  locus_session* s = nullptr;
  if (locus_session_create_from_file(argv[1], &s) != LOCUS_OK) { std::puts(locus_last_error_message()); return 1; }
  const int64_t n = locus_session_vertex_count(s);
  std::vector<double> d(n), uv(2 * n);
  std::vector<int32_t> labels(n);
  const char* names[3] = {"geodesic", "logmap", "cvt"};
  for (int call = 0; call < 3; ++call) {
    g_routed_n = g_routed_b = g_other_n = g_other_b = 0;
    if (g_sites) g_sites->clear();
    g_on = true;
    locus_status st = call == 0 ? locus_geodesic_distance(s, 0, d.data())
                      : call == 1 ? locus_logmap(s, 7, 0.1, uv.data())
                                  : locus_cvt(s, 500, 3, 1, labels.data());
    g_on = false;
    std::printf("%s: status %d; >=64KB routed %ld blocks %.1f MB; not routed %ld blocks %.1f MB (%.1f%% of bytes routed)\n",
                names[call], st, g_routed_n.load(), g_routed_b / 1e6, g_other_n.load(), g_other_b / 1e6,
                100.0 * g_routed_b / std::max(1L, g_routed_b.load() + g_other_b.load()));
    std::vector<std::pair<long, std::string>> top;
    if (g_sites) for (auto& [k, v] : *g_sites) top.push_back({v.bytes, k + " n=" + std::to_string(v.n)});
    std::sort(top.rbegin(), top.rend());
    for (size_t i = 0; i < top.size() && i < 14; ++i) std::printf("SITE %.1f MB %s\n", top[i].first / 1e6, top[i].second.c_str());
  }
  std::vector<std::pair<long, std::string>> top;
  if (g_sites) for (auto& [k, v] : *g_sites) top.push_back({v.bytes, k + " n=" + std::to_string(v.n)});
  std::sort(top.rbegin(), top.rend());
  for (size_t i = 0; i < top.size() && i < 25; ++i) std::printf("SITE %.1f MB %s\n", top[i].first / 1e6, top[i].second.c_str());
  locus_session_destroy(s);
  return 0;
}
