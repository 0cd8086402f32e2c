// Comma-separated lists on the command line (--vertices 1,5,9; --ts 1h2,10h2;
// --source 3,4): shared by the local-solve commands (adf, hks, heat).
// Header-only; every malformed entry is a usage error naming it.
#pragma once
#include <charconv>
#include <cstdint>
#include <string>
#include <vector>

#include "locus/error.hpp"

namespace locus::cli {

// Splits at commas; empty entries ("1,,2", trailing comma) are usage errors.
inline std::vector<std::string> split_list(const std::string& text, const std::string& option) {
  std::vector<std::string> items;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item.empty()) fail(ErrorCode::BadUsage, option + ": empty entry in '" + text + "'");
    items.push_back(std::move(item));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

// Vertex ids in 0..nv-1, order and repetitions kept.
inline std::vector<int32_t> parse_vertex_list(const std::string& text, int32_t nv, const std::string& option) {
  std::vector<int32_t> ids;
  for (const std::string& item : split_list(text, option)) {
    int64_t v = -1;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (ec != std::errc() || ptr != item.data() + item.size())
      fail(ErrorCode::BadUsage, option + ": '" + item + "' is not a vertex index");
    if (v < 0 || v >= nv)
      fail(v < 0 ? ErrorCode::BadUsage : ErrorCode::BadInput, option + ": vertex " + item + " is outside 0.." + std::to_string(nv - 1) +
                                    " (the mesh has " + std::to_string(nv) + " vertices)");
    ids.push_back(static_cast<int32_t>(v));
  }
  return ids;
}

// The ids of a list before the mesh is read (the requests' vertex fields):
// malformed or negative entries are usage errors, as in parse_vertex_list.
inline std::vector<int64_t> parse_vertex_ids(const std::string& text, const std::string& option) {
  std::vector<int64_t> ids;
  for (const std::string& item : split_list(text, option)) {
    int64_t v = -1;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (ec != std::errc() || ptr != item.data() + item.size())
      fail(ErrorCode::BadUsage, option + ": '" + item + "' is not a vertex index");
    if (v < 0)
      fail(ErrorCode::BadUsage, option + ": vertex " + item + " is negative (ids are 0-based)");
    ids.push_back(v);
  }
  return ids;
}

// The ids against the file's mesh of nv vertices: Error(BadInput) for one
// beyond it (the refusal depends on the file), worded as parse_vertex_list.
inline void check_file_vertices(const std::vector<int64_t>& ids, int32_t nv, const std::string& option) {
  for (int64_t v : ids)
    if (v >= nv)
      fail(ErrorCode::BadInput, option + ": vertex " + std::to_string(v) + " is outside 0.." + std::to_string(nv - 1) +
                                    " (the mesh has " + std::to_string(nv) + " vertices)");
}

}  // namespace locus::cli
