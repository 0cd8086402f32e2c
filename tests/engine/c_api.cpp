// Tests for the C API (engine/include/locus/locus.h): status codes and
// messages for every kind of bad argument, results equal to the C++ Session
// (itself checked against oracles in tests/engine/session.cpp) and to
// great-circle distances, NaN outside the log-map patch, progress and
// cancellation through the callback, per-thread error messages.
#include "locus/locus.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/session.hpp"

using namespace locus;

namespace {

struct Arrays {
  std::vector<double> xyz;
  std::vector<int32_t> tris;
  int64_t nv = 0, nf = 0;
};

Arrays arrays_of(const Mesh& m) {
  Arrays a;
  a.nv = m.num_vertices();
  a.nf = m.num_faces();
  for (int32_t i = 0; i < m.num_vertices(); ++i) a.xyz.insert(a.xyz.end(), {m.x[i], m.y[i], m.z[i]});
  a.tris.assign(m.face_vertices.begin(), m.face_vertices.end());
  return a;
}

bool message_has(const char* what) { return std::string(locus_last_error_message()).find(what) != std::string::npos; }

struct SessionGuard {
  locus_session* s = nullptr;
  ~SessionGuard() { locus_session_destroy(s); }
};

}  // namespace

TEST_CASE("c api: version, defaults, null and out-of-range arguments of session creation") {
  int32_t major = -1, minor = -1, patch = -1;
  const std::string v = locus_version(&major, &minor, &patch);
  CHECK(major == LOCUS_VERSION_MAJOR);
  CHECK(v == std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch));
  CHECK(locus_version(nullptr, nullptr, nullptr) == v);
  const locus_run_options o = locus_run_options_default();
  CHECK(o.threads == 0);
  CHECK(!o.progress);
  CHECK(o.t_factor == 0.0);  // each method's default

  const Arrays a = arrays_of(make_icosphere(2));
  locus_session* s = reinterpret_cast<locus_session*>(0x1);  // must be reset to NULL on failure
  CHECK(locus_session_create(nullptr, a.nv, a.tris.data(), a.nf, &s) == LOCUS_BAD_USAGE);
  CHECK(s == nullptr);
  CHECK(message_has("xyz is NULL"));
  CHECK(locus_session_create(a.xyz.data(), a.nv, nullptr, a.nf, &s) == LOCUS_BAD_USAGE);
  CHECK(message_has("tris is NULL"));
  CHECK(locus_session_create(a.xyz.data(), a.nv, a.tris.data(), a.nf, nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("out is NULL"));
  CHECK(locus_session_create(a.xyz.data(), 0, a.tris.data(), a.nf, &s) == LOCUS_BAD_USAGE);
  CHECK(locus_session_create(a.xyz.data(), -5, a.tris.data(), a.nf, &s) == LOCUS_BAD_USAGE);
  CHECK(locus_session_create(a.xyz.data(), int64_t(1) << 40, a.tris.data(), a.nf, &s) == LOCUS_BAD_USAGE);
  CHECK(locus_session_create(a.xyz.data(), a.nv, a.tris.data(), 0, &s) == LOCUS_BAD_USAGE);
  CHECK(message_has("no faces"));
  CHECK(locus_session_create(a.xyz.data(), a.nv, a.tris.data(), int64_t(1) << 40, &s) == LOCUS_BAD_USAGE);
  CHECK(s == nullptr);

  Arrays bad = a;
  bad.tris[7] = static_cast<int32_t>(a.nv);  // ids out of range: usage errors, as locus.h promises
  CHECK(locus_session_create(bad.xyz.data(), bad.nv, bad.tris.data(), bad.nf, &s) == LOCUS_BAD_USAGE);
  CHECK(message_has(("triangle 2 references vertex " + std::to_string(a.nv)).c_str()));
  bad = a;
  bad.tris[0] = -1;
  CHECK(locus_session_create(bad.xyz.data(), bad.nv, bad.tris.data(), bad.nf, &s) == LOCUS_BAD_USAGE);
  bad = a;
  bad.xyz[10] = std::numeric_limits<double>::quiet_NaN();
  CHECK(locus_session_create(bad.xyz.data(), bad.nv, bad.tris.data(), bad.nf, &s) == LOCUS_BAD_INPUT);
  CHECK(message_has("vertex 3"));
  bad = a;
  bad.xyz[0] = INFINITY;
  CHECK(locus_session_create(bad.xyz.data(), bad.nv, bad.tris.data(), bad.nf, &s) == LOCUS_BAD_INPUT);
  // Defects the robust operator takes (the default, auto) and the cotan one refuses.
  locus_session_options cotan{};
  cotan.mesh_operator = LOCUS_OPERATOR_COTAN;
  bad = a;  // a repeated corner: zero-area triangle
  bad.tris[1] = bad.tris[0];
  CHECK(locus_session_create_ex(bad.xyz.data(), bad.nv, bad.tris.data(), bad.nf, &cotan, &s) == LOCUS_BAD_INPUT);
  CHECK(s == nullptr);
  REQUIRE(locus_session_create(bad.xyz.data(), bad.nv, bad.tris.data(), bad.nf, &s) == LOCUS_OK);
  CHECK(locus_session_operator(s) == LOCUS_OPERATOR_ROBUST);
  locus_session_destroy(s);
  s = nullptr;
  bad = a;  // an extra vertex no face uses
  bad.xyz.insert(bad.xyz.end(), {3.0, 3.0, 3.0});
  CHECK(locus_session_create_ex(bad.xyz.data(), bad.nv + 1, bad.tris.data(), bad.nf, &cotan, &s) == LOCUS_BAD_INPUT);
  CHECK(s == nullptr);
  REQUIRE(locus_session_create(bad.xyz.data(), bad.nv + 1, bad.tris.data(), bad.nf, &s) == LOCUS_OK);
  CHECK(locus_session_operator(s) == LOCUS_OPERATOR_ROBUST);
  locus_session_destroy(s);
  s = nullptr;

  CHECK(locus_session_create_from_file(nullptr, &s) == LOCUS_BAD_USAGE);
  CHECK(locus_session_create_from_file("", &s) == LOCUS_BAD_USAGE);
  CHECK(locus_session_create_from_file("/nonexistent/mesh.off", &s) == LOCUS_BAD_INPUT);
  CHECK(message_has("/nonexistent/mesh.off"));
  CHECK(locus_session_create_from_file(LOCUS_TEST_DATA_DIR "/bcsstk01.rsa", &s) == LOCUS_BAD_INPUT);
  CHECK(s == nullptr);

  CHECK(locus_session_vertex_count(nullptr) == -1);
  CHECK(message_has("NULL"));
  locus_session_destroy(nullptr);

  CHECK(locus_session_create(a.xyz.data(), a.nv, a.tris.data(), a.nf, &s) == LOCUS_OK);
  CHECK(std::string(locus_last_error_message()).empty());
  CHECK(locus_session_vertex_count(s) == a.nv);
  CHECK(locus_session_face_count(s) == a.nf);
  locus_session_destroy(s);
}

TEST_CASE("c api: queries equal the C++ Session; bad query arguments; NaN outside the log-map patch") {
  const Mesh m = make_icosphere(3);
  const Arrays a = arrays_of(m);
  SessionGuard g;
  REQUIRE(locus_session_create(a.xyz.data(), a.nv, a.tris.data(), a.nf, &g.s) == LOCUS_OK);
  const Session ref(m);
  const size_t n = static_cast<size_t>(a.nv);

  std::vector<double> d(n);
  REQUIRE(locus_geodesic_distance(g.s, 5, d.data()) == LOCUS_OK);
  CHECK(d == ref.geodesic_distance(5));
  const double far = std::acos(std::clamp(m.x[5] * m.x[200] + m.y[5] * m.y[200] + m.z[5] * m.z[200], -1.0, 1.0));
  CHECK(std::abs(d[200] - far) < 0.05);

  CHECK(locus_geodesic_distance(nullptr, 5, d.data()) == LOCUS_BAD_USAGE);
  CHECK(message_has("session is NULL"));
  CHECK(locus_geodesic_distance(g.s, 5, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance(g.s, -1, d.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance(g.s, a.nv, d.data()) == LOCUS_BAD_USAGE);
  CHECK(message_has(std::to_string(a.nv).c_str()));
  CHECK(locus_geodesic_distance(g.s, int64_t(1) << 33, d.data()) == LOCUS_BAD_USAGE);
  locus_run_options o = locus_run_options_default();
  o.t_factor = -2;
  CHECK(locus_geodesic_distance_ex(g.s, 5, d.data(), &o) == LOCUS_BAD_USAGE);
  CHECK(message_has("t_factor"));
  o = locus_run_options_default();
  o.threads = -3;
  CHECK(locus_geodesic_distance_ex(g.s, 5, d.data(), &o) == LOCUS_BAD_USAGE);
  locus_run_options zero{};  // all zero: the defaults
  std::vector<double> d0(n);
  CHECK(locus_geodesic_distance_ex(g.s, 5, d0.data(), &zero) == LOCUS_OK);
  CHECK(d0 == d);
  o = locus_run_options_default();
  o.t_factor = 2.0;
  CHECK(locus_geodesic_distance_ex(g.s, 5, d0.data(), &o) == LOCUS_OK);
  CHECK(d0 == ref.geodesic_distance(5, HeatQuery{2.0}));

  std::vector<double> uv(2 * n);
  REQUIRE(locus_logmap(g.s, 7, 0.1, uv.data()) == LOCUS_OK);
  const LogMapResult lr = ref.logmap(7, 0.1);
  std::vector<uint8_t> in(n, 0);
  for (size_t k = 0; k < lr.patch.size(); ++k) {
    in[lr.patch[k]] = 1;
    CHECK(uv[2 * lr.patch[k]] == lr.u[k]);
    CHECK(uv[2 * lr.patch[k] + 1] == lr.v[k]);
  }
  size_t nan_count = 0;
  for (size_t i = 0; i < n; ++i)
    if (!in[i]) nan_count += std::isnan(uv[2 * i]) && std::isnan(uv[2 * i + 1]);
  CHECK(nan_count == n - lr.patch.size());
  CHECK(uv[14] == 0.0);  // the center maps to the origin
  CHECK(locus_logmap(g.s, 7, 0.0, uv.data()) == LOCUS_BAD_USAGE);
  CHECK(message_has("fraction"));
  CHECK(locus_logmap(g.s, 7, 1.01, uv.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_logmap(g.s, 7, std::numeric_limits<double>::quiet_NaN(), uv.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_logmap(g.s, 7, 0.1, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_logmap(g.s, -7, 0.1, uv.data()) == LOCUS_BAD_USAGE);

  std::vector<int32_t> labels(n, -1);
  REQUIRE(locus_cvt(g.s, 10, 2, 3, labels.data()) == LOCUS_OK);
  CHECK(labels == ref.cvt(10, 2, 3).label);
  std::vector<double> sites(30);
  CHECK(locus_cvt_ex(g.s, 10, 2, 3, labels.data(), sites.data(), nullptr) == LOCUS_OK);
  CHECK(sites == ref.cvt(10, 2, 3).site_xyz);
  CHECK(locus_cvt(g.s, 0, 2, 3, labels.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_cvt(g.s, static_cast<int32_t>(a.nv) + 1, 2, 3, labels.data()) == LOCUS_BAD_INPUT);
  CHECK(locus_cvt(g.s, 10, -1, 3, labels.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_cvt(g.s, 10, 2000000000, 3, labels.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_cvt(g.s, 10, 2, 3, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_cvt(nullptr, 10, 2, 3, labels.data()) == LOCUS_BAD_USAGE);

  const int64_t src[] = {0, 3}, tgt[] = {1, 2, 3};
  double hv[6];
  REQUIRE(locus_heat_values(g.s, src, 2, tgt, 3, hv, nullptr) == LOCUS_OK);
  CHECK(std::vector<double>(hv, hv + 6) == ref.heat_values(std::vector<int32_t>{0, 3}, std::vector<int32_t>{1, 2, 3}));
  CHECK(hv[1 * 3 + 2] > hv[1 * 3 + 0]);  // heat from 3 is largest at 3
  CHECK(locus_heat_values(g.s, src, 0, tgt, 3, hv, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_heat_values(g.s, src, 2, tgt, -1, hv, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_heat_values(g.s, src, int64_t(1) << 20, tgt, int64_t(1) << 20, hv, nullptr) == LOCUS_BAD_USAGE);
  const int64_t bad_tgt[] = {1, a.nv};
  CHECK(locus_heat_values(g.s, src, 2, bad_tgt, 2, hv, nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("targets[1]"));
  CHECK(locus_heat_values(g.s, nullptr, 2, tgt, 3, hv, nullptr) == LOCUS_BAD_USAGE);

  // set_positions: scale by 2 doubles distances.
  std::vector<double> xyz2 = a.xyz;
  for (double& c : xyz2) c *= 2;
  std::vector<double> pos(3 * n);
  REQUIRE(locus_session_get_positions(g.s, pos.data()) == LOCUS_OK);
  CHECK(pos == a.xyz);
  CHECK(locus_session_get_positions(g.s, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_session_get_positions(nullptr, pos.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_session_set_positions(g.s, xyz2.data(), a.nv - 1) == LOCUS_BAD_USAGE);
  CHECK(locus_session_set_positions(g.s, nullptr, a.nv) == LOCUS_BAD_USAGE);
  REQUIRE(locus_session_set_positions(g.s, xyz2.data(), a.nv) == LOCUS_OK);
  std::vector<double> d2(n);
  REQUIRE(locus_geodesic_distance(g.s, 5, d2.data()) == LOCUS_OK);
  for (size_t i = 0; i < n; ++i) CHECK(d2[i] == doctest::Approx(2 * d[i]).epsilon(1e-9).scale(1));
  xyz2[4] = std::numeric_limits<double>::quiet_NaN();
  CHECK(locus_session_set_positions(g.s, xyz2.data(), a.nv) == LOCUS_BAD_INPUT);
  REQUIRE(locus_session_get_positions(g.s, pos.data()) == LOCUS_OK);
  CHECK(pos[4] == 2 * a.xyz[4]);  // the failed call kept the scaled positions
}

namespace {

struct ProgressLog {
  int calls = 0;
  int cancel_after = -1;  // -1: never
  double last = -1;
  bool monotone_in_range = true;
};

int on_progress(double fraction, const char* phase, void* user) {
  auto* log = static_cast<ProgressLog*>(user);
  if (!(fraction >= 0 && fraction <= 1) || phase == nullptr) log->monotone_in_range = false;
  ++log->calls;
  log->last = fraction;
  return log->cancel_after >= 0 && log->calls > log->cancel_after ? 1 : 0;
}

}  // namespace

TEST_CASE("c api: progress callback, cancellation, per-thread error messages") {
  const Arrays a = arrays_of(make_icosphere(3));
  SessionGuard g;
  REQUIRE(locus_session_create(a.xyz.data(), a.nv, a.tris.data(), a.nf, &g.s) == LOCUS_OK);
  std::vector<int32_t> labels(static_cast<size_t>(a.nv));

  ProgressLog log;
  locus_run_options o = locus_run_options_default();
  o.progress = on_progress;
  o.user_data = &log;
  REQUIRE(locus_cvt_ex(g.s, 8, 4, 1, labels.data(), nullptr, &o) == LOCUS_OK);
  CHECK(log.calls >= 4);  // at least one report per Lloyd iteration
  CHECK(log.monotone_in_range);
  CHECK(log.last == 1.0);

  ProgressLog stop;
  stop.cancel_after = 1;
  o.user_data = &stop;
  CHECK(locus_cvt_ex(g.s, 8, 50, 1, labels.data(), nullptr, &o) == LOCUS_CANCELLED);
  CHECK(message_has("cancel"));
  CHECK(stop.calls <= 3);  // no report after the cancel request

  std::vector<double> d(static_cast<size_t>(a.nv));
  ProgressLog stop0;
  stop0.cancel_after = 0;
  o.user_data = &stop0;
  CHECK(locus_geodesic_distance_ex(g.s, 1, d.data(), &o) == LOCUS_CANCELLED);
  CHECK(locus_geodesic_distance(g.s, 1, d.data()) == LOCUS_OK);  // not poisoned by the cancelled build
  CHECK(d[1] == 0.0);

  // The message is per thread: a failure on another thread does not touch ours.
  CHECK(locus_geodesic_distance(g.s, -1, d.data()) == LOCUS_BAD_USAGE);
  const std::string mine = locus_last_error_message();
  std::string theirs;
  std::thread t([&] {
    CHECK(std::string(locus_last_error_message()).empty());
    locus_logmap(g.s, 0, 2.0, nullptr);
    theirs = locus_last_error_message();
  });
  t.join();
  CHECK(locus_last_error_message() == mine);
  CHECK(theirs != mine);
  CHECK(!theirs.empty());
}

TEST_CASE("c api: cvt remesh equals the Session's; stats; bad arguments") {
  const Mesh m = make_icosphere(3);
  const Arrays a = arrays_of(m);
  SessionGuard g;
  REQUIRE(locus_session_create(a.xyz.data(), a.nv, a.tris.data(), a.nf, &g.s) == LOCUS_OK);
  const Session ref(m);
  locus_remesh* r = nullptr;
  REQUIRE(locus_cvt_remesh(g.s, 60, 4, 2, nullptr, &r) == LOCUS_OK);
  REQUIRE(r != nullptr);
  locus_remesh_stats st;
  REQUIRE(locus_remesh_get_stats(r, &st) == LOCUS_OK);
  const CvtResult want = ref.cvt(60, 4, 2, {}, true);
  REQUIRE(want.remeshed);
  CHECK(st.vertices == static_cast<int64_t>(want.remesh_xyz.size() / 3));
  CHECK(st.faces == 2 * st.vertices - 4);  // a closed genus-0 surface
  CHECK(st.manifold == 1);
  CHECK(st.genus == 0);
  CHECK(st.components == 1);
  CHECK(st.boundary_loops == 0);
  CHECK(st.added_sites == want.added_sites);
  CHECK(st.mean_min_angle_deg == want.mean_min_angle_deg);
  CHECK(st.hausdorff_rel > 0);
  std::vector<double> xyz(3 * static_cast<size_t>(st.vertices));
  std::vector<int32_t> tris(3 * static_cast<size_t>(st.faces));
  REQUIRE(locus_remesh_get(r, xyz.data(), tris.data()) == LOCUS_OK);
  CHECK(xyz == want.remesh_xyz);
  CHECK(tris == want.remesh_triangles);
  CHECK(locus_remesh_get(r, nullptr, nullptr) == LOCUS_OK);
  locus_remesh_destroy(r);
  locus_remesh_destroy(nullptr);
  locus_remesh* none = nullptr;
  CHECK(locus_cvt_remesh(g.s, 0, 4, 2, nullptr, &none) == LOCUS_BAD_USAGE);
  CHECK(locus_cvt_remesh(g.s, 60, -1, 2, nullptr, &none) == LOCUS_BAD_USAGE);
  CHECK(locus_cvt_remesh(g.s, 60, 4, 2, nullptr, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_cvt_remesh(nullptr, 60, 4, 2, nullptr, &none) == LOCUS_BAD_USAGE);
  CHECK(none == nullptr);
  CHECK(locus_remesh_get(nullptr, xyz.data(), tris.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_remesh_get_stats(nullptr, &st) == LOCUS_BAD_USAGE);
}

TEST_CASE("c api: the last-error pointer stays valid; the copy is whole, cut or sized on request") {
  const char* p = locus_last_error_message();
  CHECK(locus_session_vertex_count(nullptr) == -1);
  const std::string first = locus_last_error_message();
  CHECK(first == "locus_session_vertex_count: session is NULL");
  CHECK(locus_last_error_message() == p);  // same buffer, new content
  // An evaluation-order trap: the pointer is read before the call
  // that fails and used after it. It must not dangle, and holds that call's message.
  locus_session* s = nullptr;
  const char* early = locus_last_error_message();
  const locus_status st = locus_session_create_from_file("/nonexistent/dir/with/a/long/name/mesh.off", &s);
  CHECK(st == LOCUS_BAD_INPUT);
  CHECK(std::string(early).find("/nonexistent/dir/with/a/long/name/mesh.off") != std::string::npos);

  const std::string whole = locus_last_error_message();
  const int64_t n = locus_last_error_copy(nullptr, 0);
  CHECK(n == static_cast<int64_t>(whole.size()));
  std::vector<char> buf(static_cast<size_t>(n) + 1, 'x');
  CHECK(locus_last_error_copy(buf.data(), n + 1) == n);
  CHECK(std::string(buf.data()) == whole);
  char small[8];
  std::fill(small, small + 8, 'x');
  CHECK(locus_last_error_copy(small, 8) == n);
  CHECK(std::string(small) == whole.substr(0, 7));
  char one = 'x';
  CHECK(locus_last_error_copy(&one, 1) == n);
  CHECK(one == '\0');
  CHECK(locus_last_error_copy(small, -3) == n);  // nothing written, nothing cleared
  CHECK(std::string(locus_last_error_message()) == whole);

  // A message longer than the pointer's buffer: the copy has it whole.
  const std::string long_path = "/nonexistent/" + std::string(5000, 'a') + ".off";
  CHECK(locus_session_create_from_file(long_path.c_str(), &s) == LOCUS_BAD_INPUT);
  const int64_t m = locus_last_error_copy(nullptr, 0);
  CHECK(m > 5000);
  std::vector<char> big(static_cast<size_t>(m) + 1);
  locus_last_error_copy(big.data(), m + 1);
  CHECK(std::string(big.data()).find(long_path) != std::string::npos);
  CHECK(std::strlen(locus_last_error_message()) == 4095);
  CHECK(std::string(big.data()).compare(0, 4095, locus_last_error_message()) == 0);

  // The next call clears it, for both forms.
  locus_session_destroy(nullptr);
  CHECK(locus_last_error_copy(nullptr, 0) == 0);
  CHECK(locus_last_error_message()[0] == '\0');
}
