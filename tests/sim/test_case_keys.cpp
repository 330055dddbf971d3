// The key table (sim/keys.hpp) is the one declaration of the common case keys: the README's
// case-key table says what it says, and a case and its typed Setup take their defaults from it.
#define BOOST_TEST_MODULE case_keys
#include <boost/test/unit_test.hpp>

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "sim/case.hpp"
#include "sim/keys.hpp"

using namespace pcsim::sim;

namespace {

std::string readme() {
  std::ifstream in(std::string(PCSIM_SOURCE_DIR) + "/README.md", std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// The second cell of the README's case-key table row for `[section]` (in "## Case files").
std::string row(const std::string& text, const std::string& section) {
  const auto from = text.find("## Case files");
  BOOST_REQUIRE(from != std::string::npos);
  const std::string start = "| `[" + section + "]` | ";
  const auto b = text.find(start, from);
  BOOST_REQUIRE_MESSAGE(b != std::string::npos, "README has no case-key row " + start);
  const auto e = text.find(" |\n", b + start.size());
  return text.substr(b + start.size(), e - b - start.size());
}

struct Mention {
  std::string key;
  std::string detail;  ///< the text in parentheses after the key, "" if none
};

/// The keys a row names at its top level (`key`, optionally followed by " (detail)").
std::vector<Mention> mentions(const std::string& cell) {
  std::vector<Mention> out;
  int depth = 0;
  for (std::size_t i = 0; i < cell.size(); ++i) {
    const char ch = cell[i];
    if (ch == '(') ++depth;
    else if (ch == ')') --depth;
    else if (ch == '`' && depth == 0) {
      const auto end = cell.find('`', i + 1);
      BOOST_REQUIRE(end != std::string::npos);
      Mention m{cell.substr(i + 1, end - i - 1), ""};
      i = end;
      if (cell.compare(i + 1, 2, " (") == 0) {
        std::size_t j = i + 3;
        int d = 1;
        for (; j < cell.size() && d > 0; ++j) d += cell[j] == '(' ? 1 : cell[j] == ')' ? -1 : 0;
        m.detail = cell.substr(i + 3, j - 1 - (i + 3));
        i = j - 1;
      }
      out.push_back(m);
    }
  }
  return out;
}

/// The detail split at "; " and ", ".
std::vector<std::string> parts(const std::string& detail) {
  std::vector<std::string> out;
  std::string cur;
  for (std::size_t i = 0; i < detail.size(); ++i) {
    if ((detail[i] == ';' || detail[i] == ',') && i + 1 < detail.size() && detail[i + 1] == ' ') {
      out.push_back(cur);
      cur.clear();
      ++i;
    } else {
      cur += detail[i];
    }
  }
  out.push_back(cur);
  return out;
}

double number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  BOOST_REQUIRE_MESSAGE(end != text.c_str(), "a number in '" + text + "'");
  return v;
}

/// Checks what the README says of one key against the key table; returns how many statements.
int check(const KeySpec& k, const std::string& detail) {
  int said = 0;
  for (const std::string& p : parts(detail)) {
    const std::string what = k.dotted() + ": README says '" + p + "'";
    if (p.rfind("default ", 0) == 0) {
      ++said;
      const std::string v = p.substr(8);
      if (k.type == KeySpec::Type::string) {
        BOOST_TEST_REQUIRE(k.string_default.has_value(), what);
        BOOST_TEST(v == "`" + *k.string_default + "`", what);
      } else if (k.type == KeySpec::Type::boolean) {
        BOOST_TEST_REQUIRE(k.bool_default.has_value(), what);
        BOOST_TEST(v == (*k.bool_default ? "`true`" : "`false`"), what);
      } else if (!k.number_default) {
        BOOST_TEST(v == k.default_text, what);
      } else {
        BOOST_TEST(number(v) == *k.number_default, what);
        if (v.find(" s") != std::string::npos) BOOST_TEST(k.unit == "s", what);
      }
    } else if (p.front() == '`' && p.find("`/`") != std::string::npos) {
      ++said;
      std::set<std::string> listed;
      std::size_t i = 0;
      while ((i = p.find('`', i)) != std::string::npos) {
        const auto e = p.find('`', i + 1);
        listed.insert(p.substr(i + 1, e - i - 1));
        i = e + 1;
      }
      BOOST_TEST((listed == std::set<std::string>(k.choices.begin(), k.choices.end())), what);
    } else if (const auto dots = p.find(" … "); dots != std::string::npos) {
      ++said;
      std::string lo = p.substr(0, dots);
      const bool excl = lo.rfind("> ", 0) == 0;
      if (excl) lo = lo.substr(2);
      BOOST_TEST(number(lo) == k.min, what);
      BOOST_TEST(excl == k.min_exclusive, what);
      BOOST_TEST(number(p.substr(dots + 5)) == k.max, what);
      BOOST_TEST(!k.max_exclusive, what);
    } else if (p.rfind("≥ ", 0) == 0) {
      ++said;
      BOOST_TEST(number(p.substr(4)) == k.min, what);
      BOOST_TEST(!k.min_exclusive, what);
    }
  }
  return said;
}

}  // namespace

BOOST_AUTO_TEST_CASE(readme_case_key_table_is_the_key_table) {
  const std::string text = readme();
  int statements = 0;
  for (const std::string section : {"solver", "output", "contact"}) {
    const std::string cell = row(text, section);
    std::set<std::string> named;
    for (const Mention& m : mentions(cell)) {
      const KeySpec* k = nullptr;
      for (const auto& spec : common_keys())
        if (spec.section == section && spec.name == m.key) k = &spec;
      BOOST_TEST_REQUIRE(k != nullptr, "README names [" + section + "] " + m.key +
                                            ", which is not in the key table");
      named.insert(m.key);
      statements += check(*k, m.detail);
    }
    for (const auto& spec : common_keys())
      if (spec.section == section)
        BOOST_TEST(named.count(spec.name) == 1,
                   "the README's [" + section + "] row does not name " + spec.name);
  }
  // The rows state the defaults of [solver] and [output], choices and ranges: 12 defaults,
  // 4 choice lists, 4 ranges, and contact.switching's default. A README that states more (or
  // fewer) updates this count, so that a statement the parser no longer sees cannot pass.
  BOOST_TEST(statements == 27, "the README's case-key rows make " << statements
                                   << " statements of defaults, choices and ranges");
}

// A case without solver keys gets the key table's defaults, in its table and in its Setup.
BOOST_AUTO_TEST_CASE(defaults_come_from_the_key_table) {
  const Case c = load_case_text("model = \"pendulum\"\n", "pendulum.toml");
  const Setup& s = c.setup;
  BOOST_TEST(s.rtol == *common_key("solver.rtol").number_default);
  BOOST_TEST(s.atol == *common_key("solver.atol").number_default);
  BOOST_TEST(s.t_end == *common_key("solver.t_end").number_default);
  BOOST_TEST(s.h0 == *common_key("solver.h0").number_default);
  BOOST_TEST(s.dt == *common_key("output.dt").number_default);
  BOOST_TEST(s.max_steps == *common_key("solver.max_steps").number_default);
  BOOST_TEST(s.contact.max_events == *common_key("contact.max_events").number_default);
  BOOST_TEST(s.contact.zeno_time == *common_key("contact.zeno_time").number_default);
  BOOST_TEST(s.contact.switching == *common_key("contact.switching").bool_default);
  BOOST_TEST(s.contact.lcp_solver == *common_key("contact.lcp_solver").string_default);
  BOOST_TEST(!s.equilibrium_start);
  // Filled keys are written into the table; counts keep their default in the Setup alone.
  BOOST_TEST(*c.table.at_path("solver.rtol").value<double>() == s.rtol);
  BOOST_TEST(*c.table.at_path("solver.method").value<std::string>() ==
             *common_key("solver.method").string_default);
  BOOST_TEST(!c.table.at_path("solver.max_steps"));
  // The schema of the case holds every common key (the pendulum has no excitation period, so
  // no output.summary_periods) with the key table's declaration.
  const auto keys = case_keys(c);
  for (const auto& k : common_keys()) {
    const KeySpec* found = nullptr;
    for (const auto& s2 : keys)
      if (s2.dotted() == k.dotted()) found = &s2;
    if (k.dotted() == "output.summary_periods") {
      BOOST_TEST(!found);
      continue;
    }
    BOOST_TEST_REQUIRE(found != nullptr, k.dotted());
    BOOST_TEST(found->meaning == k.meaning);
  }
}

// A direct edit of the table, then retype, gives the Setup of the edited case.
BOOST_AUTO_TEST_CASE(retype_follows_an_edit) {
  Case c = load_case_text("model = \"pendulum\"\n", "pendulum.toml");
  c.table["solver"].as_table()->insert_or_assign("t_end", 2.5);
  BOOST_TEST(c.setup.t_end == 10.0);
  retype(c);
  BOOST_TEST(c.setup.t_end == 2.5);
  BOOST_TEST(c.setup.window.time == 2.5);  // no period: the whole run
}
