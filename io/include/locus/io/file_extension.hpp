// The lower-case extension of a file name ("Mesh.PLY" -> "ply", "" without
// one); readers and writers dispatch on it. Internal to io/.
#pragma once
#include <string>

namespace locus::io {

inline std::string lower_extension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot + 1);
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return ext;
}

}  // namespace locus::io
