// The .npy header of output.format = "npy" (sim/row_writer.hpp, NumPy's format description:
// magic "\x93NUMPY", version 1.0 with a 2-byte header length or 2.0 with a 4-byte one when the
// header exceeds 65535 bytes, the dictionary padded with spaces and ended by '\n' so that the
// data start at a multiple of 64 bytes). Checked: that layout for 1 to 9000 columns, the version
// switch, the fields' types, and that the row count rewritten at the end keeps the length (the
// header is rewritten in place over the one written first). numpy.load itself reads the files
// in tests/python/test_npy.py.
#define BOOST_TEST_MODULE npy_header
#include <boost/test/unit_test.hpp>

#include <string>
#include <vector>

#include "sim/row_writer.hpp"

using pcsim::sim::npy_header;

namespace {
std::size_t declared_length(const std::string& h) {
  const auto b = [&](std::size_t i) { return static_cast<std::size_t>(static_cast<unsigned char>(h[i])); };
  return h[6] == 1 ? b(8) | b(9) << 8 : b(8) | b(9) << 8 | b(10) << 16 | b(11) << 24;
}
}  // namespace

BOOST_AUTO_TEST_CASE(the_header_is_numpys_layout_for_any_number_of_columns) {
  for (int n : {1, 7, 300, 3000, 9000}) {
    BOOST_TEST_CONTEXT(n << " columns") {
      std::vector<std::string> names;
      for (int i = 0; i < n; ++i) names.push_back("q" + std::to_string(i) + "_d");
      names.push_back("mode_contact");
      const std::string h = npy_header(names, 1, 7, 0);
      BOOST_TEST(h.compare(0, 6, "\x93NUMPY") == 0);
      const bool v2 = h[6] == 2;
      BOOST_TEST((h[6] == 1 || v2));
      BOOST_TEST(h[7] == '\0');
      const std::size_t prefix = v2 ? 12 : 10;
      BOOST_TEST(declared_length(h) + prefix == h.size());
      BOOST_TEST(h.size() % 64 == 0u);
      BOOST_TEST(h.back() == '\n');
      BOOST_TEST(v2 == (h.size() > 65535 + 10));
      BOOST_TEST(h.find("('q0_d', '<f8')") != std::string::npos);
      BOOST_TEST(h.find("('mode_contact', '|S7')") != std::string::npos);
      BOOST_TEST(h.find("'fortran_order': False") != std::string::npos);
      // The final count, written over the first header, leaves every byte after it in place.
      const std::string end = npy_header(names, 1, 7, 12345678901234ULL);
      BOOST_TEST(end.size() == h.size());
      BOOST_TEST(end.find("'shape': (      12345678901234,)") != std::string::npos);
    }
  }
  // 9000 columns need format 2.0, 3000 fit 1.0.
  std::vector<std::string> many(9000, "x");
  BOOST_TEST(npy_header(many, 0, 1, 0)[6] == 2);
  std::vector<std::string> some(3000, "x");
  BOOST_TEST(npy_header(some, 0, 1, 0)[6] == 1);
}

BOOST_AUTO_TEST_CASE(a_quote_in_a_name_is_escaped_as_python_reads_it) {
  const std::string h = npy_header({"a'b", "c\\d"}, 0, 1, 2);
  BOOST_TEST(h.find("('a\\'b', '<f8')") != std::string::npos);
  BOOST_TEST(h.find("('c\\\\d', '<f8')") != std::string::npos);
}
