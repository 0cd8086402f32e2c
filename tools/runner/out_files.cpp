// The names of `locus run`'s files in its --out folder, and reading them back.
#include "tools/runner/out_files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "locus/error.hpp"

namespace locus::runner {

namespace fs = std::filesystem;

fs::path report_path(const fs::path& out_dir, const std::string& stem) { return out_dir / (stem + ".json"); }

fs::path output_path(const fs::path& out_dir, const std::string& stem, const std::string& ext) {
  return out_dir / (stem + "." + ext);
}

fs::path preview_path(const fs::path& out_dir, const std::string& stem) { return out_dir / (stem + ".png"); }

fs::path summary_path(const fs::path& out_dir, int shard, int shards) {
  if (shards <= 1) return out_dir / "summary.json";
  return out_dir / ("summary-" + std::to_string(shard) + "-of-" + std::to_string(shards) + ".json");
}

std::string make_capture(const fs::path& out_dir, const std::string& stem, const char* kind) {
  std::string tmpl = (out_dir / ("." + stem + "." + kind + ".XXXXXX")).string();
  const int fd = ::mkostemp(tmpl.data(), O_CLOEXEC);
  if (fd < 0)
    fail(ErrorCode::BadInput, "run: cannot create a capture file in " + out_dir.string() + ": " + std::strerror(errno));
  ::close(fd);
  return tmpl;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace locus::runner
