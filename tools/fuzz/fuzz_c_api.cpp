// libFuzzer target for the C API entry points that take arrays
// (engine/include/locus/locus.h): locus_session_create (vertex and face counts,
// face indices out of range, NaN/Inf coordinates, zero faces), then, on a
// session, locus_session_set_positions, locus_geodesic_distance, locus_logmap,
// locus_cvt and locus_heat_values with fuzzed ids and counts, and NULL
// pointers.
//
// Input layout (missing bytes read as 0):
//   byte 0: nv (0..63), byte 1: nf (0..63), byte 2: flags
//     bit 0: raw coordinates (8 bytes each, any double, NaN and Inf included)
//            instead of small integers on a grid (which mostly give valid meshes)
//     bit 1: raw face indices (4 bytes each, any int32) instead of one byte each
//            mapped to -1..nv (so one value is -1 and one is nv: out of range)
//     bit 2: pass the counts as large int64 (2^31, 2^40) with the same arrays
//            when the mesh is otherwise read (counts are checked before the
//            arrays are read, so this must be refused without touching them)
//   then the coordinates, the faces, then query parameters.
// Findings: LOCUS_INTERNAL, a status outside the header's list, an empty error
// message after a failure, NaN in a geodesic distance or a heat value returned
// with LOCUS_OK, a label out of range, and any crash or sanitizer report.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "locus/locus.h"

namespace {

struct Reader {
  const uint8_t* data;
  size_t size, pos = 0;
  uint8_t byte() { return pos < size ? data[pos++] : 0; }
  template <class T>
  T raw() {
    unsigned char b[sizeof(T)] = {};
    for (size_t i = 0; i < sizeof(T); ++i) b[i] = byte();
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
  }
};

// Known open finding, kept out of the way so the fuzzer can look for others:
// locus_cvt on a mesh with a component that receives no site (localized Lloyd
// leaves its labels at -1, and pipelines/src/voronoi/cvt_lloyd.cpp build_cells indexes
// offsets[-1 + 1] / fill[-1]: heap-buffer-overflow; input
// tests/fuzz_corpus/c_api/regress_cvt_component_without_site). Set to false
// once cvt_lloyd handles it; the regression input then runs again.
constexpr bool kSkipCvtOnSeveralComponents = false;  // cvt_lloyd refuses siteless components since the fix

// Number of connected components of the vertices used by the triangles (union-find).
int components(int64_t nv, const std::vector<int32_t>& tris) {
  std::vector<int64_t> parent(static_cast<size_t>(nv));
  for (int64_t v = 0; v < nv; ++v) parent[v] = v;
  auto find = [&](int64_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (size_t k = 0; k + 2 < tris.size(); k += 3)
    for (int c = 0; c < 2; ++c) parent[find(tris[k + c])] = find(tris[k + c + 1]);
  int count = 0;
  for (int64_t v = 0; v < nv; ++v) count += find(v) == v;
  return count;
}

[[noreturn]] void finding(const char* what, int status) {
  std::fprintf(stderr, "fuzz_c_api: %s (status %d, message '%s')\n", what, status, locus_last_error_message());
  std::abort();
}

// Every status must be one the header lists, never INTERNAL; failures carry a message.
void check_status(locus_status s, const char* call) {
  switch (s) {
    case LOCUS_OK:
      if (locus_last_error_message()[0] != '\0') finding(call, s);
      return;
    case LOCUS_BAD_USAGE:
    case LOCUS_BAD_INPUT:
    case LOCUS_NUMERICAL:
    case LOCUS_CANCELLED:
      if (locus_last_error_message()[0] == '\0') finding(call, s);
      return;
    default:
      finding(call, s);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Reader in{data, size};
  const int64_t nv = in.byte() % 64, nf = in.byte() % 64;
  const uint8_t flags = in.byte();
  std::vector<double> xyz(static_cast<size_t>(3 * nv));
  for (double& c : xyz) c = (flags & 1) ? in.raw<double>() : static_cast<double>(static_cast<int8_t>(in.byte())) / 8.0;
  std::vector<int32_t> tris(static_cast<size_t>(3 * nf));
  for (int32_t& t : tris) t = (flags & 2) ? in.raw<int32_t>() : static_cast<int32_t>(in.byte() % (nv + 2)) - 1;

  // NULL pointers and absurd counts are refused up front.
  locus_session* s = nullptr;
  check_status(locus_session_create(nullptr, nv, tris.data(), nf, &s), "create(NULL xyz)");
  if (s) finding("create(NULL xyz) returned a session", 0);
  check_status(locus_session_create(xyz.data(), nv, tris.data(), nf, nullptr), "create(NULL out)");
  if (flags & 4) {
    check_status(locus_session_create(xyz.data(), int64_t(1) << 31, tris.data(), nf, &s), "create(nv = 2^31)");
    if (s) finding("create(nv = 2^31) returned a session", 0);
    check_status(locus_session_create(xyz.data(), nv, tris.data(), int64_t(1) << 40, &s), "create(nf = 2^40)");
    if (s) finding("create(nf = 2^40) returned a session", 0);
    check_status(locus_session_create(xyz.data(), -nv, tris.data(), nf, &s), "create(nv < 0)");
    if (s) finding("create(nv < 0) returned a session", 0);
  }
  const locus_status st = locus_session_create(xyz.empty() ? nullptr : xyz.data(), nv,
                                               tris.empty() ? nullptr : tris.data(), nf, &s);
  check_status(st, "create");
  if (st != LOCUS_OK) {
    if (s) finding("failed create returned a session", st);
    return 0;
  }
  if (!s) finding("create returned OK without a session", st);
  if (locus_session_vertex_count(s) != nv || locus_session_face_count(s) != nf) finding("counts differ", 0);

  locus_run_options opt = locus_run_options_default();
  opt.threads = 1 + in.byte() % 2;
  const uint8_t q = in.byte();
  if (q & 1) {  // new positions: fuzzed, possibly NaN or degenerate
    std::vector<double> p(xyz.size());
    for (double& c : p) c = (q & 2) ? in.raw<double>() : static_cast<double>(static_cast<int8_t>(in.byte())) / 8.0;
    check_status(locus_session_set_positions(s, p.data(), (q & 4) ? nv + 1 : nv), "set_positions");
  }
  if (q & 8) opt.t_factor = in.raw<double>();
  std::vector<double> dist(static_cast<size_t>(nv));
  const int64_t source = static_cast<int64_t>(in.byte()) - 2;  // -2 .. 253: out of range too
  locus_status r = locus_geodesic_distance_ex(s, source, dist.data(), &opt);
  check_status(r, "geodesic_distance");
  if (r == LOCUS_OK)
    for (double d : dist)
      if (std::isnan(d)) finding("NaN geodesic distance with LOCUS_OK", r);

  std::vector<double> uv(static_cast<size_t>(2 * nv));
  const int64_t center = static_cast<int64_t>(in.byte()) - 2;
  const double fraction = (q & 16) ? in.raw<double>() : (1 + in.byte() % 8) / 8.0;
  r = locus_logmap_ex(s, center, fraction, uv.data(), &opt);
  check_status(r, "logmap");
  if (r == LOCUS_OK && !std::isfinite(uv[2 * center])) finding("log map not finite at its center", r);

  const int32_t sites = static_cast<int32_t>(in.byte() % 8) - 1, iters = in.byte() % 3;
  std::vector<int32_t> labels(static_cast<size_t>(nv));
  std::vector<double> site_xyz(sites > 0 ? 3 * static_cast<size_t>(sites) : 0);
  const uint64_t seed = in.raw<uint64_t>();
  if (!kSkipCvtOnSeveralComponents || components(nv, tris) == 1) {
    r = locus_cvt_ex(s, sites, iters, seed, labels.data(), site_xyz.empty() ? nullptr : site_xyz.data(), &opt);
    check_status(r, "cvt");
    if (r == LOCUS_OK)
      for (int32_t l : labels)
        if (l < 0 || l >= sites) finding("cvt label out of range", r);
  }

  const int64_t ns = in.byte() % 5, nt = in.byte() % 5;
  std::vector<int64_t> src(static_cast<size_t>(ns)), tgt(static_cast<size_t>(nt));
  for (int64_t& v : src) v = static_cast<int64_t>(in.byte()) - 2;
  for (int64_t& v : tgt) v = static_cast<int64_t>(in.byte()) - 2;
  std::vector<double> heat(static_cast<size_t>(ns * nt));
  r = locus_heat_values(s, src.empty() ? nullptr : src.data(), ns, tgt.empty() ? nullptr : tgt.data(), nt,
                        heat.empty() ? nullptr : heat.data(), &opt);
  check_status(r, "heat_values");
  if (r == LOCUS_OK)
    for (double h : heat)
      if (!std::isfinite(h)) finding("non-finite heat value with LOCUS_OK", r);

  check_status(locus_geodesic_distance(nullptr, 0, dist.data()), "geodesic_distance(NULL session)");
  check_status(locus_geodesic_distance(s, 0, nullptr), "geodesic_distance(NULL out)");
  locus_session_destroy(s);
  return 0;
}
