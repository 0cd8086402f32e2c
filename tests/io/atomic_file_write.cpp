// Safe writes (io/include/locus/io/atomic_file_write.hpp):
// hostile conditions never lose or truncate an existing file.
#include <doctest/doctest.h>

#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "locus/io/atomic_file_write.hpp"
#include "tests/io/io_test_support.hpp"

namespace fs = std::filesystem;
using locus_test::catch_error;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path d = locus_test::scratch_dir() / ("atomic_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void spit(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

// Files in `d` other than the ones named (leftover temporaries).
std::set<std::string> names_in(const fs::path& d) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(d)) out.insert(e.path().filename().string());
  return out;
}

}  // namespace

TEST_CASE("atomic write: replaces a file whole and leaves an unrelated PATH.tmp alone") {
  const fs::path d = fresh_dir("tmp");
  const fs::path target = d / "c.locus";
  spit(target, "old");
  spit(d / "c.locus.tmp", "unrelated user file");
  locus::io::write_file_atomically(target.string(), std::string("new content"));
  CHECK(slurp(target) == "new content");
  CHECK(slurp(d / "c.locus.tmp") == "unrelated user file");
  CHECK(names_in(d) == std::set<std::string>{"c.locus", "c.locus.tmp"});
  // A plain create's permissions (not mkstemp's 0600), an existing file's kept.
  struct stat st {};
  REQUIRE(::stat(target.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) != 0600);
  ::chmod(target.c_str(), 0640);
  locus::io::write_file_atomically(target.string(), std::string("again"));
  REQUIRE(::stat(target.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0640);
}

TEST_CASE("atomic write: folders, fifos and missing folders are refused before writing") {
  const fs::path d = fresh_dir("kinds");
  fs::create_directory(d / "sub.ply");
  REQUIRE(::mkfifo((d / "pipe.ply").c_str(), 0644) == 0);
  auto e = catch_error([&] { locus::io::write_file_atomically((d / "sub.ply").string(), std::string("x")); });
  CHECK(e.code == locus::ErrorCode::BadUsage);
  CHECK(e.has("is a folder"));
  e = catch_error([&] { locus::io::write_file_atomically((d / "pipe.ply").string(), std::string("x")); });
  CHECK(e.code == locus::ErrorCode::BadUsage);
  CHECK(e.has("not a regular file"));
  e = catch_error([&] { locus::io::check_output_path((d / "no" / "x.ply").string()); });
  CHECK(e.has("does not exist"));
  CHECK(fs::is_fifo(d / "pipe.ply"));
  CHECK(fs::is_directory(d / "sub.ply"));
  CHECK(names_in(d) == std::set<std::string>{"pipe.ply", "sub.ply"});
  // A symlink to a regular file: the target file is replaced, the link stays.
  spit(d / "real.obj", "old");
  fs::create_symlink(d / "real.obj", d / "link.obj");
  locus::io::write_file_atomically((d / "link.obj").string(), std::string("new"));
  CHECK(fs::is_symlink(d / "link.obj"));
  CHECK(slurp(d / "real.obj") == "new");
}

TEST_CASE("atomic write: a file-size limit fails cleanly and keeps the old file") {
  const fs::path d = fresh_dir("fsize");
  const fs::path target = d / "mesh.ply";
  const std::string old(90 * 1024, 'o');
  spit(target, old);
  rlimit saved {};
  REQUIRE(::getrlimit(RLIMIT_FSIZE, &saved) == 0);
  rlimit small = saved;
  small.rlim_cur = 256 * 1024;
  auto previous = std::signal(SIGXFSZ, SIG_IGN);  // as the CLI does: EFBIG instead of death
  REQUIRE(::setrlimit(RLIMIT_FSIZE, &small) == 0);
  auto e = catch_error([&] { locus::io::write_file_atomically(target.string(), std::string(1 << 20, 'n')); });
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previous);
  CHECK(e.code == locus::ErrorCode::ResourceLimit);
  CHECK(e.has("write failed"));
  CHECK(slurp(target) == old);
  CHECK(names_in(d) == std::set<std::string>{"mesh.ply"});
}

TEST_CASE("atomic write: concurrent writers to one path leave one whole version") {
  const fs::path d = fresh_dir("race");
  const fs::path target = d / "out.obj";
  const std::string a(200000, 'a'), b(300000, 'b');
  auto writer = [&](const std::string& bytes) {
    for (int k = 0; k < 25; ++k) locus::io::write_file_atomically(target.string(), bytes);
  };
  std::thread t1(writer, a), t2(writer, b);
  t1.join();
  t2.join();
  const std::string got = slurp(target);
  CHECK((got == a || got == b));
  CHECK(names_in(d) == std::set<std::string>{"out.obj"});
}

TEST_CASE("atomic write: a commit group is all or nothing") {
  const fs::path d = fresh_dir("group");
  spit(d / "a.ply", "old a");
  {
    locus::io::CommitGroup g;
    locus::io::write_file_atomically((d / "a.ply").string(), std::string("new a"));
    locus::io::write_file_atomically((d / "b.png").string(), std::string("new b"));
    CHECK(slurp(d / "a.ply") == "old a");  // staged, not yet in place
    CHECK(!fs::exists(d / "b.png"));
    // destroyed without commit: the command failed
  }
  CHECK(slurp(d / "a.ply") == "old a");
  CHECK(names_in(d) == std::set<std::string>{"a.ply"});
  {
    locus::io::CommitGroup g;
    locus::io::write_file_atomically((d / "a.ply").string(), std::string("new a"));
    locus::io::write_file_atomically((d / "b.png").string(), std::string("new b"));
    g.commit();
  }
  CHECK(slurp(d / "a.ply") == "new a");
  CHECK(slurp(d / "b.png") == "new b");
  CHECK(names_in(d) == std::set<std::string>{"a.ply", "b.png"});
}
