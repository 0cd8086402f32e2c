// Safe writes: every file locus writes is written under a
// unique temporary name in the target's folder (mkstemp), fsynced, given the
// permissions a plain create would give, and renamed into place. A full disk,
// a file-size limit, a crash or a concurrent writer never leaves a truncated
// file under the real name, never touches an unrelated `PATH.tmp`, and never
// replaces anything but a regular file (a device node, a folder or a fifo as
// target is refused before anything is written).
//
// A CommitGroup makes the outputs of one command all-or-nothing: while a group
// is active on the calling thread, writes are staged (written and synced) and
// renamed into place only by CommitGroup::commit(); a group destroyed without
// commit() removes its staged files, so the targets stay as they were.
#pragma once
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "locus/core/non_copyable.hpp"

namespace locus::io {

// Checks that `path` may be replaced: its folder exists and is writable, and
// `path` is absent, a regular file, or a symlink to one (the symlink's target
// is what gets replaced). Error(BadUsage) naming the path and the reason.
void check_output_path(const std::string& path);

// One file being written under a temporary name beside its target.
class StagedFile {
 public:
  // check_output_path(path), then creates the temporary (".NAME.XXXXXX").
  explicit StagedFile(const std::string& path);
  ~StagedFile();  // removes the temporary unless committed
  StagedFile(const StagedFile&) = delete;
  StagedFile& operator=(const StagedFile&) = delete;

  std::ostream& stream();
  // Flushes, fsyncs and closes the temporary. A failed write (full disk, file
  // size limit) raises Error(ResourceLimit), any other I/O error
  // Error(BadInput), naming the target; the temporary is removed.
  void finish();
  // Renames the finished temporary onto the target (then fsyncs the folder).
  void commit();
  const std::string& target() const { return target_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string target_;
};

// Writes made on this thread while a group is alive are committed together.
class CommitGroup : NonCopyable {
 public:
  CommitGroup();
  ~CommitGroup();
  // Renames every staged file into place, in the order they were written.
  void commit();
  // Takes ownership of a finished file (used by write_file_atomically).
  void add(std::unique_ptr<StagedFile> f);
  static CommitGroup* active();

 private:
  std::vector<std::unique_ptr<StagedFile>> staged_;
  CommitGroup* previous_ = nullptr;
};

// Writes `body`'s output (or `bytes`) to `path` as described above: renamed
// at once, or staged in the thread's active CommitGroup.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& body);
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace locus::io
