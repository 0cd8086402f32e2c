// Writing a file under a temporary name and renaming it into place, so that a
// crash or a full disk never leaves a half-written file under the real name
// (factor caches, previews). Internal to io/.
#pragma once
#include <cstdio>
#include <fstream>
#include <string>

#include "locus/error.hpp"

namespace locus::io {

// `body(out)` writes the content; failures raise Error(BadInput) naming `path`
// and remove the temporary file.
template <class Body>
void write_file_atomically(const std::string& path, Body&& body) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail(ErrorCode::BadInput, path + ": cannot open for writing");
    body(out);
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      fail(ErrorCode::BadInput, path + ": write failed (disk full?)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    fail(ErrorCode::BadInput, path + ": cannot rename " + tmp + " to it");
  }
}

}  // namespace locus::io
