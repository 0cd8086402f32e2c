// Field lists of the engine's sources: a C options or report struct and its
// engine counterpart (a request, a report), or an engine report and the
// kernels' or pipelines' result it is made of, share field names, so each
// pair names its fields once, in one list, and the same list fills the C
// defaults from a default request, the request from the caller's options, and
// a report from a result. Without it every command held up to three
// hand-written copies of the same assignments, and a field added to one copy
// but not the others went unnoticed. Not installed.
//
// LOCUS_COPY_FIELDS(to, from, a, b, c) is `to.a = from.a; to.b = from.b; ...`
// through assign_field(): numbers convert (C's int flags to bool and back), a
// C string sets an engine string only when it is neither NULL nor "" (NULL
// and "" mean the request's default), other fields are copied.
#pragma once
#include <cstring>
#include <string>
#include <type_traits>

namespace locus::c_api_detail {

template <class To, class From>
  requires std::is_arithmetic_v<To> && std::is_arithmetic_v<From>
void assign_field(To& to, From from) {
  to = static_cast<To>(from);
}

inline void assign_field(std::string& to, const char* from) {
  if (from && from[0]) to = from;
}

// Any other field of the same type on both sides (a vector, a string): a copy.
template <class T>
  requires(!std::is_arithmetic_v<T>)
void assign_field(T& to, const T& from) {
  to = from;
}

// A C options struct zeroed (its strings NULL: the request's defaults), then
// `numbers(o, Request{})` (a LOCUS_COPY_FIELDS of the numeric options).
template <class Options, class Request, class Numbers>
Options c_defaults(Numbers numbers) {
  Options o;
  std::memset(&o, 0, sizeof o);
  numbers(o, Request{});
  return o;
}

}  // namespace locus::c_api_detail

// A for-each over a macro's arguments (up to 256), by deferred re-expansion.
#define LOCUS_C_PARENS ()
#define LOCUS_C_EXPAND(...) LOCUS_C_EXPAND4(LOCUS_C_EXPAND4(LOCUS_C_EXPAND4(LOCUS_C_EXPAND4(__VA_ARGS__))))
#define LOCUS_C_EXPAND4(...) LOCUS_C_EXPAND3(LOCUS_C_EXPAND3(LOCUS_C_EXPAND3(LOCUS_C_EXPAND3(__VA_ARGS__))))
#define LOCUS_C_EXPAND3(...) LOCUS_C_EXPAND2(LOCUS_C_EXPAND2(LOCUS_C_EXPAND2(LOCUS_C_EXPAND2(__VA_ARGS__))))
#define LOCUS_C_EXPAND2(...) LOCUS_C_EXPAND1(LOCUS_C_EXPAND1(LOCUS_C_EXPAND1(LOCUS_C_EXPAND1(__VA_ARGS__))))
#define LOCUS_C_EXPAND1(...) __VA_ARGS__
#define LOCUS_C_FOR_EACH(macro, ...) __VA_OPT__(LOCUS_C_EXPAND(LOCUS_C_FOR_EACH_STEP(macro, __VA_ARGS__)))
#define LOCUS_C_FOR_EACH_STEP(macro, first, ...) \
  macro(first) __VA_OPT__(LOCUS_C_FOR_EACH_AGAIN LOCUS_C_PARENS(macro, __VA_ARGS__))
#define LOCUS_C_FOR_EACH_AGAIN() LOCUS_C_FOR_EACH_STEP

#define LOCUS_C_ASSIGN_FIELD(field) ::locus::c_api_detail::assign_field(locus_c_to_.field, locus_c_from_.field);
#define LOCUS_COPY_FIELDS(to, from, ...)         \
  do {                                           \
    auto& locus_c_to_ = (to);                    \
    const auto& locus_c_from_ = (from);          \
    LOCUS_C_FOR_EACH(LOCUS_C_ASSIGN_FIELD, __VA_ARGS__) \
  } while (0)

// The C defaults of a command: its options zeroed, the numbers listed copied
// from a default request.
#define LOCUS_C_DEFAULTS(Options, Request, ...)                                        \
  ::locus::c_api_detail::c_defaults<Options, Request>([](Options& o, const Request& d) { \
    LOCUS_COPY_FIELDS(o, d, __VA_ARGS__);                                              \
  })
