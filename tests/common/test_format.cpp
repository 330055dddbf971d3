// The number formatter (common/format.hpp) against what it promises: every finite double's text
// parses back to the very bits (std::from_chars) and has no more significant digits than the
// shortest correctly rounded text that does (the smallest precision p for which glibc's printf
// "%.{p}e" round-trips, an independent implementation), and special values are written as
// documented. The doubles: every special value, the ends of every
// binade (where the spacing halves), subnormals, integers, short decimals (where ties between
// shorter candidates are likeliest), and random bit patterns over the whole range.
#define BOOST_TEST_MODULE test_format
#include <boost/test/unit_test.hpp>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "common/format.hpp"

namespace {

double from_bits(std::uint64_t b) {
  double v;
  std::memcpy(&v, &b, sizeof v);
  return v;
}

std::string oracle(double v) {  // libstdc++'s own text for the special values
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// The fewest significant digits that round-trip v, by printf.
int shortest_digits(double v) {
  char buf[64];
  for (int p = 1; p <= 17; ++p) {
    std::snprintf(buf, sizeof buf, "%.*e", p - 1, v);
    if (std::strtod(buf, nullptr) == v) return p;
  }
  return 17;
}

// Significant digits of a decimal text: the mantissa's digits without leading zeros, and
// without trailing zeros when there is an exponent or a point ("280" has 3: an integer's
// trailing zeros count unless exponent form would be shorter, which the printf oracle does not
// know, so integers are compared by value only).
int significant_digits(const std::string& a, bool& integer) {
  std::string m = a.substr(0, a.find_first_of("eE"));
  integer = a.find_first_of(".eE") == std::string::npos;
  std::string d;
  for (char c : m) if (c >= '0' && c <= '9') d += c;
  const auto first = d.find_first_not_of('0');
  if (first == std::string::npos) return 1;
  d = d.substr(first);
  if (!integer) {
    const auto last = d.find_last_not_of('0');
    d = d.substr(0, last + 1);
  }
  return static_cast<int>(d.size());
}

std::string ours(double v) {
  char buf[pcsim::kMaxNumberChars];
  char* end = pcsim::write_number(buf, v);
  BOOST_REQUIRE_LE(end - buf, pcsim::kMaxNumberChars);
  return std::string(buf, end);
}

// Counts mismatches (reporting the first few) so one failure does not flood the log.
struct Checker {
  long checked = 0, failed = 0;
  void operator()(double v) {
    ++checked;
    const std::string a = ours(v);
    if (!std::isfinite(v)) {
      if (a != oracle(v) && ++failed <= 10) BOOST_ERROR("special value written as " << a);
      return;
    }
    double back = 0;
    std::from_chars(a.data(), a.data() + a.size(), back);
    if (std::memcmp(&back, &v, sizeof v) != 0) {
      if (++failed <= 10) BOOST_ERROR(a << " does not round-trip");
      return;
    }
    bool integer = false;
    const int have = significant_digits(a, integer), need = shortest_digits(v);
    // printf's p-digit text is the correctly rounded one; a shorter text may round-trip without
    // being correctly rounded, so `need` bounds the shortest from above: never more digits.
    if (!integer && have > need) {
      if (++failed <= 10) BOOST_ERROR(a << ": " << have << " significant digits, printf needs only " << need);
    }
  }
};

}  // namespace

BOOST_AUTO_TEST_CASE(special_values_and_examples) {
  BOOST_TEST(ours(0.0) == "0");
  BOOST_TEST(ours(-0.0) == "-0");
  BOOST_TEST(ours(0.3) == "0.3");
  BOOST_TEST(ours(280.0) == "280");
  BOOST_TEST(ours(1e-5) == "1e-05");
  BOOST_TEST(ours(1e5) == "1e+05");
  BOOST_TEST(ours(std::numeric_limits<double>::infinity()) == "inf");
  BOOST_TEST(ours(-std::numeric_limits<double>::infinity()) == "-inf");
  BOOST_TEST(ours(std::numeric_limits<double>::max()) == "1.7976931348623157e+308");
  BOOST_TEST(ours(std::numeric_limits<double>::denorm_min()) == "5e-324");
  BOOST_TEST(ours(std::numeric_limits<double>::quiet_NaN()) == oracle(std::numeric_limits<double>::quiet_NaN()));
  BOOST_TEST(ours(-std::numeric_limits<double>::quiet_NaN()) == oracle(-std::numeric_limits<double>::quiet_NaN()));
  BOOST_TEST(pcsim::csv_number(std::nan("")) == "");
  BOOST_TEST(pcsim::format_number(0.1 + 0.2) == "0.30000000000000004");
}

BOOST_AUTO_TEST_CASE(binade_ends_subnormals_integers) {
  Checker check;
  for (std::uint64_t be = 0; be < 2047; ++be) {  // each binade's first and last values, both signs
    for (std::uint64_t t : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{2}, std::uint64_t{3},
                            (std::uint64_t{1} << 52) - 1, (std::uint64_t{1} << 52) - 2,
                            std::uint64_t{1} << 51}) {
      check(from_bits((be << 52) | t));
      check(from_bits((std::uint64_t{1} << 63) | (be << 52) | t));
    }
  }
  for (std::uint64_t t = 1; t < 2000; ++t) check(from_bits(t));  // the smallest subnormals
  for (long i = -2000; i <= 2000; ++i) check(static_cast<double>(i));
  for (int k = 0; k < 64; ++k) {  // powers of two and their neighbours as integers
    const double p = std::ldexp(1.0, k);
    check(p); check(std::nextafter(p, 0.0)); check(std::nextafter(p, 1e300));
  }
  double p10 = 1;
  for (int k = 0; k < 23; ++k, p10 *= 10) { check(p10); check(1 / p10); }
  BOOST_TEST(check.failed == 0);
  BOOST_TEST_MESSAGE(check.checked << " doubles checked");
}

BOOST_AUTO_TEST_CASE(short_decimals) {
  // Decimals of few digits at every scale: their neighbours have ties between shorter candidates.
  Checker check;
  for (int e = -330; e <= 310; ++e) {
    for (int m = 1; m < 1000; m += 61) {
      const double v = std::strtod((std::to_string(m) + "e" + std::to_string(e)).c_str(), nullptr);
      check(v);
      check(std::nextafter(v, 0.0));
      check(std::nextafter(v, 1e308));
    }
  }
  BOOST_TEST(check.failed == 0);
}

BOOST_AUTO_TEST_CASE(random_bit_patterns) {
  Checker check;
  std::mt19937_64 rng(20261127);
  for (int i = 0; i < 60000; ++i) check(from_bits(rng()));
  // and doubles of the magnitudes a simulation writes (1e-20..1e6), uniform in their logarithm
  std::uniform_real_distribution<double> lg(-20, 6);
  for (int i = 0; i < 30000; ++i) check(std::pow(10.0, lg(rng)) * (i % 2 ? 1 : -1));
  BOOST_TEST(check.failed == 0);
}
