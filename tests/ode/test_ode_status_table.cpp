// The ODE status table has one source (bridge/pcsim_ode_status.h, the X-macro the C++ enum is
// built from); the Fortran include fortran/pcsim_ode_status.fi and the table in docs/radau.md
// are copies for their readers. This test parses both and fails if either differs from the
// source in any name, code or (for the docs) meaning, or has an entry too many or too few.
#define BOOST_TEST_MODULE ode_status_table
#include <boost/test/unit_test.hpp>

#include <cctype>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "ode/status.hpp"

namespace {

struct Entry {
  int code;
  std::string meaning;
};

std::map<std::string, Entry> source_table() {
  std::map<std::string, Entry> t;
#define PCSIM_ODE_STATUS_ROW(name, code, text) t[#name] = Entry{code, text};
  PCSIM_ODE_STATUS_TABLE(PCSIM_ODE_STATUS_ROW)
#undef PCSIM_ODE_STATUS_ROW
  return t;
}

std::string read(const std::string& relative) {
  std::ifstream in(std::string(PCSIM_SOURCE_DIR) + "/" + relative);
  BOOST_REQUIRE_MESSAGE(in, "cannot open " << relative);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

BOOST_AUTO_TEST_CASE(enum_names_codes_and_meanings_come_from_the_table) {
  const auto t = source_table();
  std::set<int> codes;
  for (const auto& [name, e] : t) {
    const auto s = static_cast<pcsim::OdeStatus>(e.code);
    BOOST_TEST(std::string(pcsim::to_string(s)) == name);
    BOOST_TEST(std::string(pcsim::meaning(s)) == e.meaning);
    BOOST_TEST(codes.insert(e.code).second, "code " << e.code << " used twice");
    if (e.code >= 0) BOOST_TEST((pcsim::ode_status_from_idid(e.code) == s));
  }
  BOOST_TEST((pcsim::ode_status_from_idid(-17) == pcsim::OdeStatus::bad_input));
  // The statuses the kernels must keep apart (issue 14) are all there.
  for (const char* needed :
       {"success", "stopped_by_callback", "root_found", "bad_input", "tolerance_too_small",
        "inconsistent_start", "missing_index_counts", "too_many_steps", "step_too_small",
        "newton_failure", "singular_matrix", "non_finite", "rhs_failed", "jacobian_failed",
        "callback_error", "stiffness_detected"})
    BOOST_TEST(t.count(needed) == 1u, needed);
}

BOOST_AUTO_TEST_CASE(fortran_include_matches_the_table) {
  const std::string text = read("fortran/pcsim_ode_status.fi");
  const std::regex param(R"(PARAMETER\s*\(\s*ODE_([A-Z0-9_]+)\s*=\s*(-?[0-9]+)\s*\))");
  std::map<std::string, int> found;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), param);
       it != std::sregex_iterator(); ++it)
    found[(*it)[1].str()] = std::stoi((*it)[2].str());
  const auto t = source_table();
  BOOST_TEST(found.size() == t.size());
  for (const auto& [name, e] : t) {
    const std::string f = upper(name);
    BOOST_TEST_CONTEXT("ODE_" << f) {
      BOOST_TEST_REQUIRE(found.count(f) == 1u);
      BOOST_TEST(found.at(f) == e.code);
    }
    // and the name is declared INTEGER (an undeclared PARAMETER would be implicitly REAL)
    BOOST_TEST(std::regex_search(text, std::regex("ODE_" + f + R"(\s*[,\n])")), f);
  }
}

BOOST_AUTO_TEST_CASE(docs_table_matches_the_table) {
  const std::string text = read("docs/radau.md");
  const auto b = text.find("<!-- ode-status-table begin -->");
  const auto e = text.find("<!-- ode-status-table end -->");
  BOOST_TEST_REQUIRE((b != std::string::npos && e != std::string::npos && b < e));
  const std::string block = text.substr(b, e - b);
  // | `name` | code | meaning |
  const std::regex row(R"(\|\s*`([a-z_]+)`\s*\|\s*(-?[0-9]+)[^|]*\|\s*([^|\n]*?)\s*\|)");
  std::map<std::string, Entry> found;
  for (auto it = std::sregex_iterator(block.begin(), block.end(), row);
       it != std::sregex_iterator(); ++it)
    found[(*it)[1].str()] = Entry{std::stoi((*it)[2].str()), (*it)[3].str()};
  const auto t = source_table();
  BOOST_TEST(found.size() == t.size());
  for (const auto& [name, en] : t) {
    BOOST_TEST_CONTEXT(name) {
      BOOST_TEST_REQUIRE(found.count(name) == 1u);
      BOOST_TEST(found.at(name).code == en.code);
      BOOST_TEST(found.at(name).meaning == en.meaning);
    }
  }
}
