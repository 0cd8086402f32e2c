// Safe writes (locus/io/atomic_file_write.hpp). Not from the
// thesis: file plumbing. POSIX only (mkostemp, fsync, rename).
#include "locus/io/atomic_file_write.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <streambuf>

#include "locus/error.hpp"

namespace locus::io {

namespace {

thread_local CommitGroup* g_active = nullptr;

std::string errno_text(int e) { return std::strerror(e); }

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  fail(ErrorCode::BadUsage, path + ": cannot write: " + why);
}

std::string parent_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string base_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// The process' umask without changing it (umask(2) would, for every thread).
mode_t current_umask() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "Umask:") {
      std::string octal;
      status >> octal;
      return static_cast<mode_t>(std::strtoul(octal.c_str(), nullptr, 8));
    }
    std::getline(status, key);
  }
  return 022;
}

// What a write to `path` replaces: the path itself, or a symlink's target.
// Refuses what must not be replaced. Returns the resolved target.
std::string resolve_target(const std::string& path) {
  if (path.empty()) refuse("(empty path)", "no file name");
  std::string target = path;
  struct stat ls {};
  if (::lstat(path.c_str(), &ls) == 0) {
    if (S_ISLNK(ls.st_mode)) {
      char buf[PATH_MAX];
      if (!::realpath(path.c_str(), buf)) refuse(path, "it is a symlink whose target does not exist");
      target = buf;
    }
    struct stat st {};
    if (::stat(target.c_str(), &st) != 0) refuse(path, errno_text(errno));
    if (S_ISDIR(st.st_mode)) refuse(path, "it is a folder");
    if (!S_ISREG(st.st_mode)) refuse(path, "it exists and is not a regular file (device, fifo or socket)");
    if (::access(target.c_str(), W_OK) != 0) refuse(path, "the existing file is read-only");
  } else if (errno != ENOENT) {
    refuse(path, errno_text(errno));
  }
  const std::string dir = parent_of(target);
  struct stat ds {};
  if (::stat(dir.c_str(), &ds) != 0) refuse(path, "folder " + dir + " does not exist");
  if (!S_ISDIR(ds.st_mode)) refuse(path, dir + " is not a folder");
  if (::access(dir.c_str(), W_OK | X_OK) != 0) refuse(path, "folder " + dir + " is not writable");
  if (base_of(target).empty()) refuse(path, "no file name");
  return target;
}

// An output buffer over a file descriptor that remembers the first error.
class FdBuf final : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd) { setp(buf_, buf_ + sizeof buf_); }
  int error() const { return error_; }
  bool drain() {
    put(pbase(), static_cast<size_t>(pptr() - pbase()));
    setp(buf_, buf_ + sizeof buf_);
    return error_ == 0;
  }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return error_ ? traits_type::eof() : traits_type::not_eof(ch);
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n < static_cast<std::streamsize>(sizeof buf_)) return std::streambuf::xsputn(s, n);
    if (!drain()) return 0;
    put(s, static_cast<size_t>(n));
    return error_ ? 0 : n;
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  void put(const char* p, size_t n) {
    while (n > 0 && error_ == 0) {
      const ssize_t w = ::write(fd_, p, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
      } else {
        p += w;
        n -= static_cast<size_t>(w);
      }
    }
  }
  int fd_;
  int error_ = 0;
  char buf_[1 << 16];
};

}  // namespace

void check_output_path(const std::string& path) { resolve_target(path); }

struct StagedFile::Impl {
  std::string target, temp;
  int fd = -1;
  mode_t mode = 0644;
  std::unique_ptr<FdBuf> buf;
  std::unique_ptr<std::ostream> os;
  bool committed = false;
};

StagedFile::StagedFile(const std::string& path) : impl_(std::make_unique<Impl>()), target_(path) {
  Impl& s = *impl_;
  s.target = resolve_target(path);
  struct stat st {};
  s.mode = ::stat(s.target.c_str(), &st) == 0 ? (st.st_mode & 07777) : (0666 & ~current_umask());
  std::string tmpl = parent_of(s.target) + "/." + base_of(s.target) + ".XXXXXX";
  s.fd = ::mkostemp(tmpl.data(), O_CLOEXEC);
  if (s.fd < 0) refuse(path, "cannot create a temporary file beside it: " + errno_text(errno));
  s.temp = tmpl;
  s.buf = std::make_unique<FdBuf>(s.fd);
  s.os = std::make_unique<std::ostream>(s.buf.get());
}

StagedFile::~StagedFile() {
  if (!impl_) return;
  if (impl_->fd >= 0) ::close(impl_->fd);
  if (!impl_->committed && !impl_->temp.empty()) ::unlink(impl_->temp.c_str());
}

std::ostream& StagedFile::stream() { return *impl_->os; }

void StagedFile::finish() {
  Impl& s = *impl_;
  if (s.fd < 0) return;
  int err = s.buf->drain() ? 0 : s.buf->error();
  if (err == 0 && ::fchmod(s.fd, s.mode) != 0) err = errno;
  if (err == 0 && ::fsync(s.fd) != 0) err = errno;
  if (::close(s.fd) != 0 && err == 0) err = errno;
  s.fd = -1;
  if (err != 0) {
    ::unlink(s.temp.c_str());
    s.temp.clear();
    const bool space = err == ENOSPC || err == EFBIG || err == EDQUOT;
    fail(space ? ErrorCode::ResourceLimit : ErrorCode::BadInput,
         target_ + ": write failed (" + errno_text(err) + "); the existing file, if any, is unchanged");
  }
}

void StagedFile::commit() {
  Impl& s = *impl_;
  finish();
  if (s.temp.empty()) fail(ErrorCode::Internal, target_ + ": committed twice");
  resolve_target(target_);  // the target may have become a device or a folder since the check
  if (::rename(s.temp.c_str(), s.target.c_str()) != 0)
    fail(ErrorCode::BadInput, target_ + ": cannot rename the written file into place: " + errno_text(errno));
  s.committed = true;
  const int dfd = ::open(parent_of(s.target).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);  // best effort: the rename itself is durable on most file systems anyway
    ::close(dfd);
  }
}

CommitGroup::CommitGroup() : previous_(g_active) { g_active = this; }

CommitGroup::~CommitGroup() { g_active = previous_; }

CommitGroup* CommitGroup::active() { return g_active; }

void CommitGroup::add(std::unique_ptr<StagedFile> f) {
  // A second write to one target in a group replaces the first staged one.
  for (auto& s : staged_)
    if (s->target() == f->target()) {
      s = std::move(f);
      return;
    }
  staged_.push_back(std::move(f));
}

void CommitGroup::commit() {
  for (auto& s : staged_) s->commit();
  staged_.clear();
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& body) {
  auto f = std::make_unique<StagedFile>(path);
  body(f->stream());
  f->finish();
  if (CommitGroup* g = CommitGroup::active())
    g->add(std::move(f));
  else
    f->commit();
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  write_file_atomically(path, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

}  // namespace locus::io
