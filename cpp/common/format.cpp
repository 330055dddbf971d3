#include "common/format.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace pcsim {

void append_number(std::string& out, double v) {
  char buf[40];
  // 40 characters always hold the shortest round-trip representation of a double (at most 24).
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  (void)ec;
  out.append(buf, end);
}

std::string format_number(double v) {
  std::string s;
  append_number(s, v);
  return s;
}

void append_csv_number(std::string& out, double v) {
  if (std::isfinite(v)) append_number(out, v);
}

std::string csv_number(double v) {
  std::string s;
  append_csv_number(s, v);
  return s;
}

std::string counted(long long n, const std::string& noun, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 || n == -1 ? noun : (plural.empty() ? noun + "s" : plural));
}

std::string format_significant(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace pcsim
