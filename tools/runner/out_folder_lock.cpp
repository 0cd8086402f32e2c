// Who may write into a --out folder (see out_folder_lock.hpp).
//
// Why a lock and not the pid in each temporary's name: the temporaries of
// locus' atomic writes (io/atomic_file_write) are named after their target
// only, the children write most of them, and shards of one run may share a
// folder from several machines, where a pid means nothing. A shared flock
// held by every live run (and inherited by its children) says exactly what is
// needed: whether any run is still writing here.
#include "tools/runner/out_folder_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <system_error>
#include <thread>

#include "locus/io/atomic_file_write.hpp"
#include "tools/runner/out_files.hpp"

namespace locus::runner {
namespace {

namespace fs = std::filesystem;

// What makes two runs' results interchangeable: everything but the inputs,
// the threads and the scheduling (results do not depend on them).
Json stamp_of(const RunOptions& o) {
  return {{"command", "run"},
          {"pipeline", o.pipeline},
          {"pipeline_options", o.pipeline_args},
          {"ext", o.ext},
          {"preview", o.preview}};
}

// The folder's stamp, null when there is none; an unreadable one is an empty object.
Json read_stamp(const fs::path& dir) {
  const fs::path p = dir / ".locus-run.json";
  std::error_code ec;
  if (!fs::exists(p, ec)) return nullptr;
  try {
    Json j = Json::parse(slurp(p));
    return j.is_object() ? j : Json::object();
  } catch (const std::exception&) {
    return Json::object();
  }
}

bool same_options(const Json& a, const Json& b) {
  for (const char* key : {"pipeline", "pipeline_options", "ext", "preview"})
    if (a.value(key, Json()) != b.value(key, Json())) return false;
  return true;
}

// `cvt --sites 20 --ext ply --preview`: the options as a user would type them.
std::string describe(const Json& stamp) {
  if (!stamp.contains("pipeline")) return "unreadable options stamp";
  std::string s = stamp.value("pipeline", "?");
  for (const Json& a : stamp.value("pipeline_options", Json::array()))
    if (a.is_string()) s += " " + a.get<std::string>();
  const std::string ext = stamp.value("ext", "");
  s += " --ext " + (ext.empty() ? std::string("none") : ext);
  if (stamp.value("preview", false)) s += " --preview";
  return s;
}

[[noreturn]] void refuse(const fs::path& dir, const Json& theirs, const Json& mine, bool live) {
  const std::string d = dir.string();
  usage_error("--out " + d + (live ? " is being written by another run" : " holds the results of another run") +
              " with other options (`" + describe(theirs) + "`; this run: `" + describe(mine) + "`). Use another --out" +
              (live ? " folder, or wait for that run to end and remove " + d + " first."
                    : " folder, or remove " + d + " first to replace those results."));
}

void remove_stale_temporaries(const fs::path& dir, const std::string& ext) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code fec;
    if (it->is_regular_file(fec) && is_locus_temporary_name(it->path().filename().string(), ext))
      fs::remove(it->path(), fec);
  }
}

// True when some item report in the folder (a STEM.json with a result) says ok.
bool holds_results(const fs::path& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name[0] == '.' || it->path().extension() != ".json") continue;
    try {
      const Json report = Json::parse(slurp(it->path()));
      if (report.is_object() && report.contains("result") && report.value("status", "") == "ok") return true;
    } catch (const std::exception&) {
    }
  }
  return false;
}

int flock_retrying(int fd, int op) {
  int rc;
  do {
    rc = ::flock(fd, op);
  } while (rc != 0 && errno == EINTR);
  return rc;
}

}  // namespace

bool is_locus_temporary_name(const std::string& name, const std::string& ext) {
  constexpr size_t kSuffix = 7;  // ".XXXXXX"
  if (name.size() < 2 + kSuffix || name[0] != '.' || name[name.size() - kSuffix] != '.') return false;
  for (size_t k = name.size() - kSuffix + 1; k < name.size(); ++k)
    if (!std::isalnum(static_cast<unsigned char>(name[k]))) return false;
  const std::string target = name.substr(1, name.size() - 1 - kSuffix);
  const size_t dot = target.rfind('.');
  if (dot == std::string::npos || dot == 0) return false;
  const std::string e = target.substr(dot + 1);
  for (const char* known : {"json", "png", "txt", "stdout", "stderr", "ply", "obj", "off", "locus"})
    if (e == known) return true;
  return !ext.empty() && e == ext;
}

OutFolderLock::OutFolderLock(const fs::path& out_dir, const RunOptions& o) : dir_(out_dir), ext_(o.ext) {
  // Not O_CLOEXEC: the children inherit the descriptor and with it the lock.
  fd_ = ::open((dir_ / ".locus-run.lock").c_str(), O_RDWR | O_CREAT, 0644);
  if (fd_ < 0) usage_error("--out " + dir_.string() + ": cannot create its lock file (" + std::strerror(errno) + ")");
  const Json mine = stamp_of(o);
  for (int attempt = 0;; ++attempt) {
    Json theirs;
    if (flock_retrying(fd_, LOCK_EX | LOCK_NB) == 0) {  // no other run is live
      theirs = read_stamp(dir_);
      if (theirs.is_null()) {
        io::write_file_atomically((dir_ / ".locus-run.json").string(), mine.dump(2) + "\n");
        stamped_ = true;
      } else if (!same_options(theirs, mine)) {
        ::close(fd_);
        refuse(dir_, theirs, mine, false);
      }
      remove_stale_temporaries(dir_, ext_);
      flock_retrying(fd_, LOCK_SH);
      return;
    }
    flock_retrying(fd_, LOCK_SH);  // waits out another run's stamping
    theirs = read_stamp(dir_);
    if (!theirs.is_null() && same_options(theirs, mine)) return;
    if (!theirs.is_null()) {
      ::close(fd_);
      refuse(dir_, theirs, mine, true);
    }
    // Live runs but no stamp (removed by hand): try again to stamp it, then go on.
    if (attempt == 20) return;
    flock_retrying(fd_, LOCK_UN);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

OutFolderLock::~OutFolderLock() {
  if (fd_ >= 0) ::close(fd_);
}

void OutFolderLock::clean_up_if_alone(bool this_run_has_results) {
  if (fd_ < 0 || flock_retrying(fd_, LOCK_EX | LOCK_NB) != 0) return;
  remove_stale_temporaries(dir_, ext_);
  std::error_code ec;
  if (stamped_ && !this_run_has_results && !holds_results(dir_)) fs::remove(dir_ / ".locus-run.json", ec);
}

}  // namespace locus::runner
