// Options spelled as words (a method, an energy): one table of (value, word)
// per enum gives both the parser the front ends call and the word reports
// print, and a refusal lists the accepted words, so the three cannot drift
// apart. Not installed.
#pragma once
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

#include "locus/error.hpp"

namespace locus {

template <class E, std::size_t N>
using EnumNames = std::array<std::pair<E, const char*>, N>;

// The value spelled `word`; BadUsage "unknown WHAT 'word' (expected a, b or c)" otherwise.
template <class E, std::size_t N>
E parse_enum_name(std::string_view word, const EnumNames<E, N>& table, const char* what) {
  for (const auto& [value, name] : table)
    if (word == name) return value;
  std::string list;
  for (std::size_t k = 0; k < N; ++k) list += std::string(k == 0 ? "" : k + 1 == N ? " or " : ", ") + table[k].second;
  fail(ErrorCode::BadUsage, "unknown " + std::string(what) + " '" + std::string(word) + "' (expected " + list + ")");
}

template <class E, std::size_t N>
const char* enum_name(E e, const EnumNames<E, N>& table) {
  for (const auto& [value, name] : table)
    if (value == e) return name;
  return "?";
}

}  // namespace locus
