#include "common/format.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace pcsim {

namespace {

// Shortest round-trip decimals, after R. Giulietti, "The Schubfach way to render doubles" (2020),
// implemented from the paper's mathematics: a double v = c 2^q has the rounding interval
// [v - ulp/2, v + ulp/2] (half that below at a power of two); scaled by 10^-k (k chosen so the
// interval is narrower than 10 units) its bounds are computed from a 126-bit approximation of
// 10^-k with one sticky bit, which decides exactly whether a multiple of 10 (one digit fewer)
// or one of the two integers next to v 10^-k lies inside. The result is the digits std::to_chars
// prints (shortest, then closest to v, then even), formatted as it does: fixed or scientific,
// whichever is shorter, fixed on a tie. tests/common/test_format checks it against
// std::to_chars character for character on about a million doubles (bench_format --verify N
// on as many more as wanted); bench/bench_format measures it.

struct G128 {
  std::uint64_t g1, g0;  // g = g1 2^63 + g0, 2^125 <= g < 2^126
};
constexpr int kKMin = -324;
constexpr G128 kPow10[] = {
#include "common/format_pow10.inc"
};

__extension__ typedef unsigned __int128 u128;  // GCC and Clang

inline std::uint64_t mul_high(std::uint64_t a, std::uint64_t b) {
  return static_cast<std::uint64_t>((static_cast<u128>(a) * b) >> 64);
}

// floor(g cp / 2^127), its lowest bit set when the quotient is inexact (the sticky bit).
inline std::uint64_t round_odd(const G128& g, std::uint64_t cp) {
  const std::uint64_t x1 = mul_high(g.g0, cp);
  const u128 y = static_cast<u128>(g.g1) * cp;
  const std::uint64_t y0 = static_cast<std::uint64_t>(y), y1 = static_cast<std::uint64_t>(y >> 64);
  const std::uint64_t z = (y0 >> 1) + x1;
  const std::uint64_t vbp = y1 + (z >> 63);
  constexpr std::uint64_t kMask63 = (std::uint64_t{1} << 63) - 1;
  return vbp | (((z & kMask63) + kMask63) >> 63);
}

inline int floor_log10_pow2(int q) { return static_cast<int>((q * 661971961083LL) >> 41); }
inline int floor_log10_three_quarters_pow2(int q) {
  return static_cast<int>((q * 661971961083LL - 274743187321LL) >> 41);
}
inline int floor_log2_pow10(int e) { return static_cast<int>((e * 913124641741LL) >> 38); }

struct Decimal {
  std::uint64_t f;  // v = f 10^e
  int e;
};

// v = c 2^q > 0 (c < 2^53).
Decimal to_decimal(int q, std::uint64_t c) {
  constexpr std::uint64_t kCMin = std::uint64_t{1} << 52;
  constexpr int kQMin = -1074;
  const std::uint64_t out = c & 1;  // an odd c: the interval's ends do not round to v
  const std::uint64_t cb = c << 2, cbr = cb + 2;
  std::uint64_t cbl;
  int k;
  if (c != kCMin || q == kQMin) {
    cbl = cb - 2;
    k = floor_log10_pow2(q);
  } else {  // a power of two: the spacing below is half that above
    cbl = cb - 1;
    k = floor_log10_three_quarters_pow2(q);
  }
  const int h = q + floor_log2_pow10(-k) + 2;
  const G128& g = kPow10[k - kKMin];
  const std::uint64_t vb = round_odd(g, cb << h), vbl = round_odd(g, cbl << h),
                      vbr = round_odd(g, cbr << h);
  const std::uint64_t s = vb >> 2;
  if (s >= 10) {  // (from 10: std::to_chars, unlike Java's Double.toString, allows one digit)
    const std::uint64_t sp10 = 10 * (s / 10), tp10 = sp10 + 10;
    const bool upin = vbl + out <= (sp10 << 2);
    const bool wpin = (tp10 << 2) + out <= vbr;
    if (upin != wpin) return {upin ? sp10 : tp10, k};
  }
  const bool uin = vbl + out <= (s << 2);
  const bool win = ((s + 1) << 2) + out <= vbr;
  if (uin != win) return {uin ? s : s + 1, k};
  const std::int64_t cmp = static_cast<std::int64_t>(vb - ((s + s + 1) << 1));
  return {cmp < 0 || (cmp == 0 && (s & 1) == 0) ? s : s + 1, k};
}

constexpr char kDigits2[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

constexpr std::uint64_t kPow10u64[] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL,
    1000000ULL, 10000000ULL, 100000000ULL, 1000000000ULL, 10000000000ULL, 100000000000ULL,
    1000000000000ULL, 10000000000000ULL, 100000000000000ULL, 1000000000000000ULL,
    10000000000000000ULL, 100000000000000000ULL, 1000000000000000000ULL};

inline int decimal_length(std::uint64_t f) {  // 0 < f < 10^18
  const int t = ((64 - __builtin_clzll(f)) * 1233) >> 12;  // floor(log10 f) or one more
  return t + (f >= kPow10u64[t] ? 1 : 0);
}

inline void write8(char* p, std::uint32_t x) {  // exactly 8 digits, leading zeros kept
  const std::uint32_t a = x / 10000, b = x % 10000;
  std::memcpy(p, kDigits2 + 2 * (a / 100), 2);
  std::memcpy(p + 2, kDigits2 + 2 * (a % 100), 2);
  std::memcpy(p + 4, kDigits2 + 2 * (b / 100), 2);
  std::memcpy(p + 6, kDigits2 + 2 * (b % 100), 2);
}

// The n digits of f (n <= 17) end at end[0]: they start at end - n.
inline void write_digits(char* end, std::uint64_t f, int n) {
  write8(end - 8, static_cast<std::uint32_t>(f % 100000000));
  if (n > 8) {
    const std::uint64_t h = f / 100000000;
    write8(end - 16, static_cast<std::uint32_t>(h % 100000000));
    if (n > 16) end[-17] = static_cast<char>('0' + h / 100000000);
  }
}

}  // namespace

char* write_number(char* p, double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  if (bits >> 63) *p++ = '-';
  const std::uint64_t t = bits & ((std::uint64_t{1} << 52) - 1);
  const int bq = static_cast<int>((bits >> 52) & 0x7ff);
  if (bq == 0x7ff) {
    std::memcpy(p, t != 0 ? "nan" : "inf", 3);  // std::to_chars writes "nan", "-nan", "inf", "-inf"
    return p + 3;
  }
  Decimal d;
  if (bq != 0) {
    const int q = bq - 1075;
    const std::uint64_t c = (std::uint64_t{1} << 52) | t;
    if (q <= 0 && q > -53 && ((c >> -q) << -q) == c) {
      d = {c >> -q, 0};  // an integer below 2^53: its own digits
    } else {
      d = to_decimal(q, c);
    }
  } else if (t == 0) {
    *p = '0';
    return p + 1;
  } else {
    d = to_decimal(-1074, t);
  }
  // The shortest digits: no trailing zeros.
  std::uint64_t f = d.f;
  int e = d.e;
  if (f % 10 == 0) {
    while (f % 100 == 0) { f /= 100; e += 2; }
    if (f % 10 == 0) { f /= 10; e += 1; }
  }
  const int n = decimal_length(f);
  const int E = e + n - 1;  // v = d.ddd 10^E
  // The digits, at dig[0..n), with at least 24 readable bytes after dig[0] for the fixed-size
  // copies below (which write past the number's end: the caller's room is kMaxNumberChars).
  char tmp[48];
  write_digits(tmp + 17, f, n);
  const char* dig = tmp + 17 - n;
  const int sci_len = n + (n > 1 ? 1 : 0) + 2 + (E >= 100 || E <= -100 ? 3 : 2);
  const int fixed_len = e >= 0 ? n + e : (E >= 0 ? n + 1 : n + 1 - E);
  if (fixed_len <= sci_len) {
    if (e > 0 && bq >= 1075) {
      // An integer of 2^52 or more: std::to_chars (as printf's %f) writes its exact value,
      // not the shortest digits padded with zeros (fixed is chosen only below ~10^22 < 2^74).
      u128 x = static_cast<u128>((std::uint64_t{1} << 52) | t) << (bq - 1075);
      char buf[40];
      char* q = buf + sizeof buf;
      do {
        *--q = static_cast<char>('0' + static_cast<int>(x % 10));
        x /= 10;
      } while (x != 0);
      const std::size_t len = static_cast<std::size_t>(buf + sizeof buf - q);
      std::memcpy(p, q, len);
      return p + len;
    }
    if (e >= 0) {  // an integer: digits then (at most 5) zeros
      std::memcpy(p, dig, 17);
      std::memcpy(p + n, "00000000", 8);
      return p + n + e;
    }
    if (E >= 0) {  // the point after E + 1 digits (E + 1 < n <= 17)
      std::memcpy(p, dig, 16);
      p[E + 1] = '.';
      std::memcpy(p + E + 2, dig + E + 1, 16);
      return p + n + 1;
    }
    // 0.ddd or 0.000ddd: at most 3 zeros after the point (else scientific is shorter)
    const int zeros = -E - 1;
    std::memcpy(p, "0.000000", 8);
    std::memcpy(p + 2 + zeros, dig, 17);
    return p + 2 + zeros + n;
  }
  // d.ddde+XX
  p[0] = dig[0];
  if (n > 1) {
    p[1] = '.';
    std::memcpy(p + 2, dig + 1, 16);
    p += n + 1;
  } else {
    p += 1;
  }
  int x = E;
  p[0] = 'e';
  p[1] = x < 0 ? '-' : '+';
  if (x < 0) x = -x;
  p += 2;
  if (x >= 100) {
    *p++ = static_cast<char>('0' + x / 100);
    x %= 100;
  }
  std::memcpy(p, kDigits2 + 2 * x, 2);
  return p + 2;
}

void append_number(std::string& out, double v) {
  char buf[kMaxNumberChars];
  out.append(buf, write_number(buf, v));
}

std::string format_number(double v) {
  std::string s;
  append_number(s, v);
  return s;
}

void append_csv_number(std::string& out, double v) {
  if (std::isfinite(v)) append_number(out, v);
}

char* write_csv_number(char* p, double v) { return std::isfinite(v) ? write_number(p, v) : p; }

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
