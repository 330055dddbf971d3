// Reading a run's time series back (sim/time_series_file.hpp), as pcsim plot and pcsim animate
// do: a timeseries.npy made of the writer's own header (npy_header) and records reads back to
// the rows that were written, bit for bit (NaN stays NaN, the labels their texts), and to the
// same rows as the CSV of those rows; its CSV text is byte for byte what the CSV writer writes;
// a header of format 2.0 (9000 columns) reads as one of 1.0.
// Every malformed file is refused with InputError naming the file and what was expected, never
// read past its end: cut off anywhere (every prefix of a file), another magic string or
// version, a header length past the end, another dtype ('>f8', '<f4', a plain '<f8' array
// without names), fortran_order True, a 2-D shape, a shape that does not match the file size,
// shapes whose byte count overflows 64 bits, a label that is not a padded mode, labels before
// numbers, a first column that is not 't', duplicate or unknown keys; any byte of the header
// changed.
#define BOOST_TEST_MODULE time_series_file
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "../support/cli_util.hpp"
#include "common/error.hpp"
#include "sim/row_writer.hpp"
#include "sim/time_series_file.hpp"

namespace fs = std::filesystem;
using pcsim::sim::read_time_series;
using pcsim::sim::TimeSeries;

namespace {

const std::vector<std::string> kNames = {"t", "x", "x_d", "fstar", "mode_u"};
const std::vector<std::string> kLabels = {"flight", "contact", "stick", "slip"};
const std::string kRerun = "rerun it";

// Rows as the run hands them to its writer: t, x, x_d, fstar (NaN in flight), the mode's index.
std::vector<double> rows() {
  return {0.0, 1.0 / 3.0, -2.5e-300, 0.25, 1,  //
          0.001, 4.9406564584124654e-324, 1e300, std::nan(""), 0,
          0.002, -0.0, 123456.789, 0.5, 3};
}

std::string npy_bytes(const std::vector<double>& values, std::size_t n_rows) {
  std::string b = pcsim::sim::npy_header(kNames, 1, 7, n_rows);
  for (std::size_t r = 0; r < n_rows; ++r) {
    b.append(reinterpret_cast<const char*>(&values[r * 5]), 4 * sizeof(double));
    const std::string& l = kLabels[static_cast<std::size_t>(values[r * 5 + 4])];
    b += l + std::string(7 - l.size(), '\0');
  }
  return b;
}

fs::path put(const std::string& name, const std::string& bytes) {
  static const fs::path dir = pcsim_test::scratch("time_series_file", "files");
  const fs::path f = dir / name;
  std::ofstream(f, std::ios::binary | std::ios::trunc) << bytes;
  return f;
}

// The message of reading `bytes` as a .npy file, "" when it reads.
std::string refusal(const std::string& bytes) {
  const fs::path f = put("bad.npy", bytes);
  try {
    read_time_series(f, std::uint64_t{1} << 30, kRerun);
  } catch (const pcsim::InputError& e) {
    return e.what();
  }
  return "";
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A header of the writer's layout around the dictionary `dict` (version 1.0, padded to 64).
std::string with_dict(std::string dict) {
  const std::size_t total = 10 + dict.size() + 1, padded = (total + 63) / 64 * 64;
  dict.append(padded - total, ' ');
  dict += '\n';
  return std::string("\x93NUMPY\x01\x00", 8) + static_cast<char>(dict.size() & 0xff) +
         static_cast<char>(dict.size() >> 8) + dict;
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_npy_reads_back_to_the_rows_written_and_the_csv_text_is_the_writers) {
  const std::vector<double> v = rows();
  const TimeSeries t = read_time_series(put("timeseries.npy", npy_bytes(v, 3)), 1 << 20, kRerun);
  BOOST_TEST(t.header == kNames, boost::test_tools::per_element());
  BOOST_TEST(t.label_columns == 1);
  BOOST_TEST_REQUIRE(t.rows() == 3u);
  for (std::size_t r = 0; r < 3; ++r) {
    for (std::size_t c = 0; c < 4; ++c) BOOST_TEST(same_bits(t.at(r, c), v[r * 5 + c]), r << "," << c);
    BOOST_TEST(t.label(r, 4) == kLabels[static_cast<std::size_t>(v[r * 5 + 4])]);
  }
  // The CSV text: the writer's header line and rows, byte for byte.
  std::string csv = pcsim::sim::csv_header_line(kNames);
  std::vector<char> line(pcsim::sim::csv_row_room(5, 1, kLabels));
  for (std::size_t r = 0; r < 3; ++r)
    csv.append(line.data(), pcsim::sim::write_csv_row(line.data(), &v[r * 5], 5, 1, kLabels));
  BOOST_TEST(pcsim::sim::time_series_csv(t) == csv);
  // That CSV read back: the same values (the empty field a NaN) and labels.
  const TimeSeries c = read_time_series(put("timeseries.csv", csv), 1 << 20, kRerun);
  BOOST_TEST(c.header == kNames, boost::test_tools::per_element());
  BOOST_TEST_REQUIRE(c.rows() == 3u);
  for (std::size_t r = 0; r < 3; ++r) {
    for (std::size_t k = 0; k < 4; ++k)
      BOOST_TEST((same_bits(c.at(r, k), t.at(r, k)) || (std::isnan(c.at(r, k)) && std::isnan(t.at(r, k)))));
    BOOST_TEST(c.label(r, 4) == t.label(r, 4));
  }
  BOOST_TEST(pcsim::sim::time_series_csv(c) == csv);
}

// 9000 columns: the writer's header takes format 2.0 (a 4-byte header length), read the same.
BOOST_AUTO_TEST_CASE(a_version_2_header_reads_as_version_1) {
  std::vector<std::string> names = {"t"};
  for (int i = 0; i < 9000; ++i) names.push_back("q" + std::to_string(i) + "_d");
  std::string b = pcsim::sim::npy_header(names, 0, 1, 2);
  BOOST_TEST_REQUIRE(b[6] == 2);
  std::vector<double> v(2 * names.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = 0.5 * static_cast<double>(i);
  b.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
  const TimeSeries t = read_time_series(put("wide.npy", b), 1 << 20, kRerun);
  BOOST_TEST(t.header == names, boost::test_tools::per_element());
  BOOST_TEST(t.values == v, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(a_file_cut_off_anywhere_is_refused_naming_the_file) {
  const std::string whole = npy_bytes(rows(), 3);
  for (std::size_t n = 0; n < whole.size(); ++n) {
    const std::string m = refusal(whole.substr(0, n));
    BOOST_TEST_CONTEXT(n << " bytes: " << m) {
      BOOST_TEST(pcsim_test::has(m, "bad.npy: "));
      if (n >= whole.size() - 3 * 39) BOOST_TEST(pcsim_test::has(m, "rows of 39 bytes"));
      if (n >= 10 && n < whole.size() - 3 * 39) BOOST_TEST(pcsim_test::has(m, "cut off"));
    }
  }
  // Bytes after the last record: the shape does not match either.
  BOOST_TEST(pcsim_test::has(refusal(whole + "x"), "header says 3 rows of 39 bytes, the file holds 118 bytes"));
}

BOOST_AUTO_TEST_CASE(what_pcsim_does_not_write_is_refused_saying_what_was_expected) {
  const std::string good = npy_bytes(rows(), 3);
  const std::size_t h = good.size() - 3 * 39;
  const std::string data = good.substr(h);
  auto header_with = [&](const std::string& from, const std::string& to) {
    std::string dict = good.substr(10, h - 10);
    const auto at = dict.find(from);
    BOOST_TEST_REQUIRE(at != std::string::npos, from);
    dict.replace(at, from.size(), to);
    while (!dict.empty() && (dict.back() == ' ' || dict.back() == '\n')) dict.pop_back();
    return with_dict(dict);
  };
  struct Bad {
    std::string bytes, expect;
  };
  const std::vector<Bad> cases = {
      {"PK\x03\x04 not a numpy file at all", "expected the magic string"},
      {std::string("\x93NUMPY\x03\x00", 8) + good.substr(8), "expected .npy format version 1.0 or 2.0, got 3.0"},
      {std::string("\x93NUMPY\x01\x00\xff\xff", 10) + good.substr(10), "is cut off after"},
      {std::string("\x93NUMPY\x02\x00\xff\xff\xff\xff", 12) + good.substr(10), "is cut off after"},
      {header_with("'<f8'", "'>f8'") + data, "expected the type '<f8' (little-endian float64)"},
      {header_with("'<f8'", "'<f4'") + data, "got '<f4'"},
      {header_with("'|S7'", "'|S0'") + data, "got '|S0'"},
      {header_with("'|S7'", "'|S99999999999999999999'") + data, "a label '|Sn'"},
      {header_with("'fortran_order': False", "'fortran_order': True") + data,
       "expected 'fortran_order': False (rows in C order), got True"},
      {header_with("'fortran_order': False", "'fortran_order': 0") + data, "expected False or True"},
      {header_with("                   3,)", "3, 5)") + data, "expected 'shape' to be one dimension (rows,)"},
      {header_with("                   3,)", "2,)") + data, "header says 2 rows of 39 bytes, the file holds 117"},
      {header_with("                   3,)", "18446744073709551615,)") + data, "header says 18446744073709551615 rows"},
      // 2^61 + 3 records of 8 bytes: their byte count wraps to the file's 24.
      {pcsim::sim::npy_header({"t"}, 0, 1, (1ULL << 61) + 3) + std::string(24, '\0'),
       "header says 2305843009213693955 rows of 8 bytes, the file holds 24 bytes"},
      {header_with("                   3,)", "18446744073709551616,)") + data, "exceeds 2^64"},
      {header_with("                   3,)", "-3,)") + data, "expected a non-negative integer in 'shape'"},
      {header_with("('x', '<f8')", "('x y', '<f8')") + data, "expected a column name"},
      {header_with("('x', '<f8')", "('t', '<f8')") + data, "the field 't' appears twice"},
      {header_with("('t', '<f8')", "('time', '<f8')") + data, "its first column 't'"},
      {header_with("'shape'", "'shape': (3,), 'shape'") + data, "the key 'shape' appears twice"},
      {header_with("'shape'", "'extra': False, 'shape'") + data, "unexpected key 'extra'"},
      {header_with(", 'fortran_order': False", "") + data, "'fortran_order' is missing"},
      {header_with("('x', '<f8')", "('x' '<f8')") + data, "expected ',' after the field name 'x'"},
      {header_with("}", "} junk") + data, "expected only spaces after the header's '}'"},
      {with_dict("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 5), }") + std::string(120, '\0'),
       "a plain array has no column names"},
      {with_dict("{'descr': [('t', '<f8'), ('mode_u', '|S7'), ('x', '<f8')], 'fortran_order': False, "
                 "'shape': (0,), }"),
       "expected the numbers before the labels"},
      {pcsim::sim::npy_header(kNames, 1, 7, 0), "no rows"},
  };
  for (const Bad& b : cases) {
    const std::string m = refusal(b.bytes);
    BOOST_TEST(pcsim_test::has(m, "bad.npy: "), m);
    BOOST_TEST(pcsim_test::has(m, b.expect), b.expect << " | " << m);
  }
  // A label that is not a mode's text padded with zero bytes.
  for (const std::string& label : {std::string("cont\0ct", 7), std::string(7, '\0'), std::string("a,b\0\0\0\0", 7)}) {
    std::string b = good;
    b.replace(h + 32, 7, label);
    BOOST_TEST(pcsim_test::has(refusal(b), "row 1, column 'mode_u': expected a mode"));
  }
}

// Every byte of the header set to each of the bytes that matter to its syntax: the header
// reads or is refused with InputError, nothing else (no other exception, no read past the end).
BOOST_AUTO_TEST_CASE(any_byte_of_the_header_changed_reads_or_is_refused) {
  const std::string good = npy_bytes(rows(), 3);
  const std::size_t h = good.size() - 3 * 39;
  int refused = 0;
  for (std::size_t i = 0; i < h; ++i)
    for (const char c : std::string("\0\n (),:'\\9[]{}\x7f\xff", 16)) {
      std::string b = good;
      b[i] = c;
      try {
        pcsim::sim::read_npy_layout(b, "bad.npy", kRerun);
      } catch (const pcsim::InputError& e) {
        ++refused;
        BOOST_TEST(pcsim_test::has(e.what(), "bad.npy: "), e.what());
      }
    }
  BOOST_TEST(refused > 0);
}

BOOST_AUTO_TEST_CASE(a_file_that_is_not_a_regular_file_or_too_large_is_refused_before_reading) {
  const fs::path dir = pcsim_test::scratch("time_series_file", "kinds");
  try {
    read_time_series(dir, 1 << 20, kRerun);
    BOOST_FAIL("a directory was read");
  } catch (const pcsim::InputError& e) {
    BOOST_TEST(pcsim_test::has(e.what(), "(a regular file)"), e.what());
  }
  const fs::path f = put("big.npy", npy_bytes(rows(), 3));
  try {
    read_time_series(f, 100, kRerun);
    BOOST_FAIL("a file over the limit was read");
  } catch (const pcsim::InputError& e) {
    BOOST_TEST(pcsim_test::has(e.what(), "big.npy: expected a pcsim time series of at most 100 bytes"), e.what());
  }
}
