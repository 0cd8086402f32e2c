// The host's process state survives locus calls: OpenBLAS'
// thread count (kernels/factor/blas.hpp borrows it), the C library's rand()
// sequence (METIS draws from its own generator: cmake/metis.cmake) and stderr
// (nothing written; an oversized thread count is clamped and said through the
// message callback instead of oneTBB's warning; an arena of 100000 threads
// made oneTBB print "TBB Warning" and crash this process when destroyed).
#include <doctest/doctest.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "locus/kernels/factor/blas.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/locus.h"

using namespace locus;

namespace {

// Redirects fd 2 to a temporary file while alive; text() is what was written.
class CaptureStderr {
 public:
  CaptureStderr() {
    std::fflush(stderr);
    char name[] = "/tmp/locus_stderr_XXXXXX";
    fd_ = mkstemp(name);
    unlink(name);
    saved_ = dup(2);
    dup2(fd_, 2);
  }
  ~CaptureStderr() { restore(); }
  std::string text() {
    restore();
    std::string s;
    char buf[4096];
    lseek(fd_, 0, SEEK_SET);
    for (ssize_t n; (n = read(fd_, buf, sizeof buf)) > 0;) s.append(buf, static_cast<size_t>(n));
    return s;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    dup2(saved_, 2);
    close(saved_);
    saved_ = -1;
  }
  int fd_ = -1, saved_ = -1;
};

struct Arrays {
  std::vector<double> xyz;
  std::vector<int32_t> tris;
  int64_t nv = 0, nf = 0;
};

Arrays sphere() {
  const Mesh m = make_icosphere(4);
  Arrays a;
  a.nv = m.num_vertices();
  a.nf = m.num_faces();
  for (int32_t i = 0; i < m.num_vertices(); ++i) a.xyz.insert(a.xyz.end(), {m.x[i], m.y[i], m.z[i]});
  a.tris.assign(m.face_vertices.begin(), m.face_vertices.end());
  return a;
}

void on_message(const char* text, void* user) { static_cast<std::vector<std::string>*>(user)->push_back(text); }

}  // namespace

TEST_CASE("host state: BLAS threads, rand() and stderr are as the host left them") {
  const int blas_before = openblas_get_num_threads();
  openblas_set_num_threads(2);
  REQUIRE(openblas_get_num_threads() == 2);  // else OpenBLAS was built with one thread and this proves nothing
  std::srand(4242);
  const int r1 = std::rand(), r2 = std::rand(), r3 = std::rand();
  std::srand(4242);
  CHECK(std::rand() == r1);

  const Arrays a = sphere();
  std::vector<std::string> notes;
  locus_run_options o = locus_run_options_default();
  o.threads = 100000;
  o.message = on_message;
  o.user_data = &notes;
  std::string err;
  {
    CaptureStderr cap;
    locus_session* s = nullptr;
    REQUIRE(locus_session_create(a.xyz.data(), a.nv, a.tris.data(), a.nf, &s) == LOCUS_OK);
    std::vector<double> d(static_cast<size_t>(a.nv)), uv(static_cast<size_t>(2 * a.nv));
    CHECK(locus_geodesic_distance_ex(s, 0, d.data(), &o) == LOCUS_OK);  // orders (METIS), factors (BLAS), solves
    CHECK(locus_logmap_ex(s, 7, 0.1, uv.data(), &o) == LOCUS_OK);
    std::vector<int32_t> labels(static_cast<size_t>(a.nv));
    CHECK(locus_cvt_ex(s, 20, 2, 1, labels.data(), nullptr, &o) == LOCUS_OK);
    locus_session_destroy(s);
    err = cap.text();
  }
  CHECK(err.empty());
  INFO("stderr: " << err);
  CHECK(openblas_get_num_threads() == 2);
  CHECK(std::rand() == r2);  // the sequence continues where the host left it
  CHECK(std::rand() == r3);
  REQUIRE(!notes.empty());
  CHECK(notes[0].find("threads = 100000") != std::string::npos);

  // Borrowed concurrently: the count comes back only after the last of several overlapping calls.
  {
    std::vector<std::thread> ts;
    for (int t = 0; t < 3; ++t)
      ts.emplace_back([&a, t] {
        locus_session* s = nullptr;
        if (locus_session_create(a.xyz.data(), a.nv, a.tris.data(), a.nf, &s) != LOCUS_OK) return;
        std::vector<double> d(static_cast<size_t>(a.nv));
        locus_geodesic_distance(s, t, d.data());
        locus_session_destroy(s);
      });
    for (auto& t : ts) t.join();
  }
  CHECK(openblas_get_num_threads() == 2);
  openblas_set_num_threads(blas_before);

}
