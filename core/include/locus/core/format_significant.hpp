// A number as messages, reports and legends print it: printf's %g with a
// given count of significant digits (3 for sizes in advice, 4 for legends, 6
// for values a user may paste back as an option). Not installed.
#pragma once
#include <cstdio>
#include <string>

namespace locus {

inline std::string format_significant(double v, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace locus
