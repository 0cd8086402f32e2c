// Helpers for the tests that run the built `locus` binary (tests/tools/):
// a scratch folder, running the tool with captured output, reading files.
#pragma once
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "locus/mesh_io.hpp"

extern char** environ;

namespace locus::test_cli {

namespace fs = std::filesystem;

inline const std::string kLocus = LOCUS_BINARY_DIR "/locus";

// The values of the named vertex property of a mesh file, read back by locus' readers.
inline std::vector<double> vertex_property(const std::string& path, const std::string& name) {
  locus::MeshAttributes a;
  locus::read_mesh(path, {}, &a);
  for (const auto& p : a.vertex)
    if (p.name == name) return p.values;
  FAIL("no property " << name << " in " << path);
  return {};
}

inline bool have_locus() {
  if (fs::exists(kLocus)) return true;
  MESSAGE("skipped: " << kLocus << " has not been built");
  return false;
}

struct Scratch {
  fs::path path;
  explicit Scratch(const std::string& tag) {
    path = fs::temp_directory_path() / ("locus-" + tag + "-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::create_directories(path);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

struct Run {
  int status = -1;  // exit status, -1 if killed by a signal
  std::string out, err;
  nlohmann::json json() const { return nlohmann::json::parse(out); }
};

// Starts `locus args...` with stdout/stderr to files in `dir`; returns the pid.
inline pid_t start_locus(const Scratch& dir, const std::vector<std::string>& args) {
  std::vector<std::string> all = {kLocus};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  const std::string out = dir / "stdout.txt", err = dir / "stderr.txt";
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, kLocus.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  REQUIRE(rc == 0);
  return pid;
}

inline Run wait_locus(const Scratch& dir, pid_t pid) {
  int ws = 0;
  while (::waitpid(pid, &ws, 0) < 0) {
  }
  Run r;
  r.status = WIFEXITED(ws) ? WEXITSTATUS(ws) : -1;
  r.out = slurp(dir / "stdout.txt");
  r.err = slurp(dir / "stderr.txt");
  return r;
}

inline Run run_locus(const Scratch& dir, const std::vector<std::string>& args) {
  return wait_locus(dir, start_locus(dir, args));
}

}  // namespace locus::test_cli
