// Parsing of site lists and surface points for the diffusion-diagram commands
// (locus nncoords, locus skinweights): "--sites 0,17,342" (vertex ids) and
// "--point f,b0,b1,b2" (a face and barycentric weights). Errors are BadUsage and
// quote the text; ranges are checked against the mesh by check_surface_point.
#pragma once
#include <climits>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/mesh.hpp"

namespace locus::cli {

inline std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t comma = text.find(',', start);
    parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return parts;
}

inline std::vector<int32_t> parse_vertex_list(const std::string& option, const std::string& text) {
  const std::string msg = option + " expects comma-separated vertex ids (e.g. " + option + " 0,17,342), got '" + text + "'";
  std::vector<int32_t> ids;
  for (const std::string& part : split_commas(text)) {
    size_t used = 0;
    long long v = -1;
    try {
      v = std::stoll(part, &used);
    } catch (const std::exception&) {
      fail(ErrorCode::BadUsage, msg);
    }
    if (used != part.size() || v < 0 || v > INT32_MAX) fail(ErrorCode::BadUsage, msg);
    ids.push_back(static_cast<int32_t>(v));
  }
  return ids;
}

inline SurfacePoint parse_surface_point(const std::string& option, const std::string& text) {
  const std::string msg = option + " expects FACE,B0,B1,B2 (a face id and three barycentric weights summing to 1), got '" + text + "'";
  const std::vector<std::string> parts = split_commas(text);
  if (parts.size() != 4) fail(ErrorCode::BadUsage, msg);
  SurfacePoint p;
  try {
    size_t used = 0;
    const long long f = std::stoll(parts[0], &used);
    if (used != parts[0].size() || f < 0 || f > INT32_MAX) fail(ErrorCode::BadUsage, msg);
    p.face = static_cast<int32_t>(f);
    for (int k = 0; k < 3; ++k) {
      p.bary[k] = std::stod(parts[k + 1], &used);
      if (used != parts[k + 1].size()) fail(ErrorCode::BadUsage, msg);
    }
  } catch (const std::logic_error&) {
    fail(ErrorCode::BadUsage, msg);
  }
  return p;
}

// Vertex ids -> surface points, each checked against the mesh (BadInput naming the entry: it depends on the file).
inline std::vector<SurfacePoint> vertex_sites(const Mesh& m, const std::string& option, const std::vector<int32_t>& ids) {
  std::vector<SurfacePoint> s;
  for (size_t k = 0; k < ids.size(); ++k) {
    if (ids[k] >= m.num_vertices())
      fail(ErrorCode::BadInput, option + " entry " + std::to_string(k) + " is vertex " + std::to_string(ids[k]) +
                                    ", but the mesh has " + std::to_string(m.num_vertices()) + " vertices");
    s.push_back(vertex_point(ids[k]));
  }
  return s;
}

}  // namespace locus::cli
