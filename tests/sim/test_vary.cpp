// Bad --vary specifications are rejected before any run, each with a message naming it
// (sim/vary.hpp, on a case of any model).
#define BOOST_TEST_MODULE study_vary
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "../support/build_tree.hpp"
#include "common/error.hpp"
#include "sim/case.hpp"
#include "sim/vary.hpp"

using namespace pcsim::sim;

namespace {

/// A case of the paper's sieve through the generic layer (its model file, no application).
Case base_case() {
  const auto dir = pcsim_test::binary_dir() / "test-scratch" / "vary";
  std::filesystem::create_directories(dir);
  const auto file = dir / "mini.toml";
  std::ofstream(file) << "model = \"" << PCSIM_SOURCE_DIR << "/models/sieve_1995.toml\"\n";
  return load_case(file, {{"solver.t_end", "0.2"}});
}

/// parse_vary(spec) throws pcsim::InputError whose message contains every `needle`.
void expect_rejected(const std::string& spec, std::initializer_list<const char*> needles) {
  const auto base = base_case();
  try {
    make_grid({spec}, base);
    BOOST_ERROR("accepted: " << spec);
  } catch (const pcsim::InputError& e) {
    const std::string what = e.what();
    for (const char* n : needles)
      BOOST_TEST(what.find(n) != std::string::npos, "'" << what << "' lacks '" << n << "'");
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(unknown_key_is_rejected_naming_it) {
  expect_rejected("parameters.omgea=1:2:3", {"unknown key", "parameters.omgea"});
  expect_rejected("omega=1:2:3", {"unknown key", "omega"});
}

BOOST_AUTO_TEST_CASE(non_numeric_key_is_rejected_naming_it) {
  expect_rejected("solver.kernel=1,2", {"not numeric", "solver.kernel"});
}

BOOST_AUTO_TEST_CASE(zero_or_non_integer_count_is_rejected) {
  expect_rejected("parameters.omega=250:300:0", {"COUNT", "at least 1"});
  expect_rejected("parameters.omega=250:300:-2", {"COUNT"});
  expect_rejected("parameters.omega=250:300:2.5", {"COUNT", "2.5", "whole number"});
  expect_rejected("parameters.omega=250:300:1", {"COUNT 1"});
}

BOOST_AUTO_TEST_CASE(reversed_range_is_rejected) {
  expect_rejected("parameters.omega=300:250:3", {"reversed range", "250", "300"});
}

BOOST_AUTO_TEST_CASE(non_numeric_value_is_rejected_naming_it) {
  expect_rejected("parameters.omega=250:abc:3", {"'abc'", "not a number"});
  expect_rejected("parameters.omega=250,28o", {"'28o'", "not a number"});
  expect_rejected("parameters.omega=250,,300", {"''", "not a number"});
  expect_rejected("parameters.omega=nan,1", {"not finite"});
}

BOOST_AUTO_TEST_CASE(malformed_specification_and_repeated_key_are_rejected) {
  expect_rejected("parameters.omega", {"expected KEY="});
  expect_rejected("parameters.omega=1:2:3:4", {"expected START:STOP:COUNT"});
  const auto base = base_case();
  BOOST_CHECK_THROW(make_grid({"parameters.omega=1,2", "parameters.omega=3"}, base),
                    pcsim::InputError);
}

BOOST_AUTO_TEST_CASE(value_the_case_rejects_is_rejected_before_running) {
  // A negative roller mass is non-physical: load_case's own validation, applied per value.
  expect_rejected("parameters.m2=-1:1:3", {"parameters.m2", "-1", "rejected by the case"});
}

BOOST_AUTO_TEST_CASE(bounds_need_low_below_high) {
  const auto base = base_case();
  const Bounds b = parse_bounds("parameters.omega=250:310", base);
  BOOST_TEST(b.low == 250.0);
  BOOST_TEST(b.high == 310.0);
  BOOST_CHECK_THROW(parse_bounds("parameters.omega=310:250", base), pcsim::InputError);
  BOOST_CHECK_THROW(parse_bounds("parameters.omega=250:250", base), pcsim::InputError);
  BOOST_CHECK_THROW(parse_bounds("parameters.omega=250:300:3", base), pcsim::InputError);
}
