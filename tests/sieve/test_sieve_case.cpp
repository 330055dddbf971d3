// Sieve case files: defaults, --set overrides with type checking, validation errors that name
// the file, the key and the expectation, and to_toml round trips.
#define BOOST_TEST_MODULE sieve_case
#include <boost/test/unit_test.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "common/error.hpp"
#include "sim/case.hpp"
#include "register.hpp"
#include "sieve/support/settings.hpp"

using namespace pcsim;
using namespace pcsim::sieve;
using namespace pcsim::sim;
namespace fs = std::filesystem;

namespace {

// A case file in a fresh temporary directory, removed at the end of the test.
struct TempCase {
  fs::path dir, file;
  explicit TempCase(const std::string& text, const std::string& name = "tmpcase.toml") {
    dir = fs::temp_directory_path() /
          ("pcsim_sieve_case_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    fs::create_directories(dir);
    file = dir / name;
    std::ofstream(file) << text;
  }
  ~TempCase() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  static int& counter() {
    static int c = 0;
    return c;
  }
};

// The error message of load_case, or "" if it loads.
std::string load_error(const fs::path& file, const std::vector<Override>& o = {}) {
  try {
    load_case(file, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

const fs::path kCase = fs::path(PCSIM_SOURCE_DIR) / "cases" / "sieve_1995.toml";

}  // namespace

BOOST_AUTO_TEST_CASE(shipped_case_loads_with_the_printed_parameters) {
  const Case c = load_case(kCase);
  BOOST_TEST(c.name == "sieve_1995");
  const SieveSettings s = settings_from_case(c);
  BOOST_TEST(s.p.m1 == 400.0);
  BOOST_TEST(s.p.J2 == 0.25e-4);
  BOOST_TEST(s.p.omega == 280.0);
  BOOST_TEST(s.q0[3] == 0.40);
  BOOST_TEST(s.q0[4] == 0.15);  // u starts at u0
  BOOST_TEST(s.constraints.contact);
  BOOST_TEST(!s.constraints.lock_theta);
  BOOST_TEST(s.output.summary_periods == 5);
}

// An almost empty file gets every documented default of sieve-model.md section 5.
BOOST_AUTO_TEST_CASE(missing_keys_take_the_documented_defaults) {
  TempCase t("model = \"sieve\"\n");
  const SieveSettings s = settings_from_case(load_case(t.file));
  BOOST_TEST(s.p.g == 9.81);
  BOOST_TEST(s.p.x0 == 0.10);
  BOOST_TEST(s.p.y0 == 0.20);
  BOOST_TEST(s.p.b == -0.20);
  BOOST_TEST(s.p.a == 0.50);
  BOOST_TEST(s.p.u0 == 0.15);
  BOOST_TEST(s.p.f == 0.3);
  BOOST_TEST(s.q0[3] == 0.40);
  BOOST_TEST(s.solver.t_end == 10.0);
  BOOST_TEST(s.output.summary_periods == 5);
  BOOST_TEST(s.constraints.rolling);
}

BOOST_AUTO_TEST_CASE(overrides_set_values_by_dotted_key_with_their_type) {
  const Case c = load_case(kCase, {{"parameters.omega", "300"},
                                   {"constraints.lock_theta", "true"},
                                   {"solver.kernel", "cpp"},
                                   {"solver.form", "\"dae\""},
                                   {"output.summary_periods", "3"}});
  const SieveSettings s = settings_from_case(c);
  BOOST_TEST(s.p.omega == 300.0);
  BOOST_TEST(s.constraints.lock_theta);
  BOOST_TEST((s.solver.kernel == Kernel::cpp));
  BOOST_TEST((s.solver.form == Form::dae));
  BOOST_TEST(s.output.summary_periods == 3);
  BOOST_TEST(parse_override("parameters.e=0.02").second == "0.02");
  BOOST_CHECK_THROW(parse_override("parameters.e"), InputError);
}

// Each error class: the message names the file, the key, and what was expected.
BOOST_AUTO_TEST_CASE(invalid_cases_are_rejected_naming_file_key_and_expectation) {
  struct Bad {
    std::string text, key, expected;
  };
  const std::vector<Bad> bad = {
      {"[parameters]\nmass = 3.0\n", "parameters.mass", "a known key"},
      {"[solvr]\nrtol = 1e-6\n", "solvr", "a known key"},
      {"[parameters]\nm1 = \"heavy\"\n", "parameters.m1", "a number"},
      {"[constraints]\ncontact = 1\n", "constraints.contact", "a boolean"},
      {"[parameters]\nm2 = -0.5\n", "parameters.m2", "a positive number"},
      {"[parameters]\nJ1 = -1.0\n", "parameters.J1", "a positive number"},
      {"[parameters]\nm0 = -1.0\n", "parameters.m0", "a non-negative number"},
      {"[parameters]\nr = 0.0\n", "parameters.r", "a positive number"},
      {"[solver]\nrtol = 0.0\n", "solver.rtol", "a number >= 1e-13"},
      {"[solver]\nt_end = -1.0\n", "solver.t_end", "a number >= 1e-09"},
      {"[solver]\nkernel = \"julia\"\n", "solver.kernel", "\"fortran\" or \"cpp\""},
      {"[solver]\nform = \"index3\"\n", "solver.form", "\"ode\" or \"dae\""},
      {"model = \"pendulm\"\n", "model", "a built-in model (pendulum, rolling_disk, sieve, slider_crank)"},
      {"model = \"no/such/model.toml\"\n", "model", "a model file"},
      {"[output]\nsummary_periods = 2.5\n", "output.summary_periods", "an integer"},
      {"[initial]\nu = 0.2\n", "initial.u", "parameters.u0"},
      {"[constraints]\nlock_theta = true\n[initial]\ntheta = 0.01\n", "initial.theta", "0"},
      {"parameters = 3\n", "parameters", "a table"},
  };
  for (const auto& b : bad) {
    TempCase t(b.text);
    const std::string msg = load_error(t.file);
    BOOST_TEST_CONTEXT(b.text) {
      BOOST_TEST(contains(msg, t.file.string()));
      BOOST_TEST(contains(msg, "'" + b.key + "'"));
      BOOST_TEST(contains(msg, "expected " + b.expected));
    }
  }
}

BOOST_AUTO_TEST_CASE(bad_overrides_are_rejected_naming_file_key_and_expectation) {
  const std::string f = kCase.string();
  std::string msg = load_error(kCase, {{"parameters.omega", "fast"}});
  BOOST_TEST(contains(msg, f));
  BOOST_TEST(contains(msg, "'parameters.omega'"));
  BOOST_TEST(contains(msg, "expected a number"));
  msg = load_error(kCase, {{"parameters.nonsense", "1"}});
  BOOST_TEST(contains(msg, "'parameters.nonsense'"));
  BOOST_TEST(contains(msg, "expected a key of the case format for the built-in model 'sieve'"));
  msg = load_error(kCase, {{"constraints.contact", "yes"}});
  BOOST_TEST(contains(msg, "expected true or false"));
  msg = load_error(kCase, {{"solver.rtol", "-1e-6"}});
  BOOST_TEST(contains(msg, "'solver.rtol'"));
  BOOST_TEST(contains(msg, "expected a number >= 1e-13"));
  // set_value on a loaded case validates the same way and leaves the case unchanged.
  Case c = load_case(kCase);
  BOOST_CHECK_THROW(set_value(c, {"parameters.r", "0"}), InputError);
  BOOST_TEST(settings_from_case(c).p.r == 0.1);
  set_value(c, {"parameters.r", "0.12"});
  BOOST_TEST(settings_from_case(c).p.r == 0.12);
  // Checks across keys name the key that breaks them: u0 >= r.
  BOOST_CHECK_THROW(set_value(c, {"parameters.r", "0.2"}), InputError);
  BOOST_TEST(contains(load_error(kCase, {{"parameters.r", "0.2"}}), "'parameters.u0'"));
}

BOOST_AUTO_TEST_CASE(malformed_toml_is_reported_with_file_and_line) {
  TempCase t("model = \"sieve\"\n[parameters\nm1 = 3\n");
  const std::string msg = load_error(t.file);
  BOOST_TEST(contains(msg, t.file.string() + ":2"));
  BOOST_TEST(contains(msg, "malformed TOML"));
}

BOOST_AUTO_TEST_CASE(numeric_keys_are_identified) {
  const Case c = load_case(kCase);
  BOOST_TEST(is_numeric_key(c, "parameters.omega"));
  BOOST_TEST(is_numeric_key(c, "initial.s0"));
  BOOST_TEST(is_numeric_key(c, "output.summary_periods"));
  BOOST_TEST(is_integer_key(c, "output.summary_periods"));
  BOOST_TEST(!is_integer_key(c, "parameters.omega"));
  BOOST_TEST(!is_numeric_key(c, "constraints.contact"));
  BOOST_TEST(!is_numeric_key(c, "solver.kernel"));
  BOOST_TEST(!is_numeric_key(c, "parameters.nonsense"));
}

// to_toml writes a file load_case reads back to an equal case: same name, same table (every
// number bit for bit, since TOML floats are written with round-trip precision).
BOOST_AUTO_TEST_CASE(to_toml_round_trips_to_an_equal_case) {
  Case c = load_case(kCase, {{"parameters.omega", "287.123456789012345"},
                             {"parameters.e", "0.0123"},
                             {"constraints.lock_theta", "true"}});
  c.name = "best_design";
  TempCase t(to_toml(c), "written_by_optimizer.toml");
  const Case back = load_case(t.file);
  BOOST_TEST(back.name == "best_design");
  toml::table expected = c.table;
  expected.insert_or_assign("name", c.name);  // to_toml makes the name explicit
  BOOST_TEST((back.table == expected));
  BOOST_TEST(settings_from_case(back).p.omega == 287.123456789012345);
}
