// Files a command wrote. Each is staged (io/include/locus/io/atomic_file_write.hpp)
// and renamed into place only when the whole command succeeded
// (CommandTable::run commits them), so "wrote <path>" is logged then, not at the
// write: a file that is rolled back is never announced.
#pragma once
#include <string>

namespace locus::cli {

// Logs "wrote <path>" once the command's files are committed (nothing if it fails).
void log_written(const std::string& path);

}  // namespace locus::cli
