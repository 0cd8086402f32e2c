// Tests for io/include/locus/io/text_scanner.hpp: number parsing edge cases against values the
// C++ standard pins down, line splitting and counting, message quoting.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "locus/io/text_scanner.hpp"
#include "io_test_support.hpp"

using namespace locus::io;

TEST_CASE("text_scanner: parse_double takes whole tokens only") {
  double d = 0;
  CHECK(parse_double("1.5", d));
  CHECK(d == 1.5);
  CHECK(parse_double("+2", d));
  CHECK(d == 2.0);
  CHECK(parse_double("-0", d));
  CHECK(std::signbit(d));
  CHECK(parse_double("4.9406564584124654e-324", d));  // smallest subnormal survives
  CHECK(d == std::numeric_limits<double>::denorm_min());
  CHECK(parse_double("1E3", d));
  CHECK(d == 1000.0);
  CHECK_FALSE(parse_double("", d));
  CHECK_FALSE(parse_double("+", d));
  CHECK_FALSE(parse_double("1.5x", d));
  CHECK_FALSE(parse_double("0x10", d));
  CHECK_FALSE(parse_double("1e999", d));  // overflow is not a value
  CHECK(parse_double("nan", d));          // parses; the readers reject non-finite coordinates
  CHECK(std::isnan(d));
}

TEST_CASE("text_scanner: parse_int range and syntax") {
  int64_t v = 0;
  CHECK(parse_int("-9223372036854775808", v));
  CHECK(v == std::numeric_limits<int64_t>::min());
  CHECK_FALSE(parse_int("9223372036854775808", v));
  CHECK(parse_int("+7", v));
  CHECK(v == 7);
  CHECK_FALSE(parse_int("+-7", v));
  CHECK_FALSE(parse_int("3.0", v));
  CHECK_FALSE(parse_int("", v));
}

TEST_CASE("text_scanner: lines, comments, BOM and line numbers") {
  const std::string name = "n.txt";
  LineReader r("\xEF\xBB\xBF" "a b\r\n\n  # c\nd # e\nlast", name);
  std::string_view line;
  REQUIRE(r.next_content(line));
  CHECK(r.line_number() == 1);
  Fields f(line);
  CHECK(f.next() == "a");
  CHECK(f.next() == "b");
  CHECK(f.next().empty());
  REQUIRE(r.next_content(line));
  CHECK(r.line_number() == 4);
  CHECK(Fields(line).next() == "d");
  REQUIRE(r.next(line));
  CHECK(line == "last");
  CHECK(r.line_number() == 5);
  CHECK_FALSE(r.next(line));
  const auto e = locus_test::catch_error([&] { r.fail("boom"); });
  CHECK(e.message == "n.txt:5: boom");
}

TEST_CASE("text_scanner: quote bounds and escapes what it prints") {
  CHECK(quote("ab") == "'ab'");
  CHECK(quote(std::string_view("\x01\xff", 2)) == "'\\x01\\xff'");
  CHECK(quote(std::string(1000, 'z')).size() == 32 + 5);  // 32 chars, "...", two quotes
}

TEST_CASE("text_scanner: saturating arithmetic for count checks") {
  const uint64_t max = std::numeric_limits<uint64_t>::max();
  CHECK(sat_mul(uint64_t(1) << 40, uint64_t(1) << 40) == max);
  CHECK(sat_mul(6, 7) == 42);
  CHECK(sat_add(max, 1) == max);
}
