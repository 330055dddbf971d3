// The check of a case at its initial state (sim/check.hpp): the fields against what the
// mechanisms are by construction (the parallelogram with a third crank: 12 coordinates, 12
// constraints, one degree of freedom, so rank 11 with one dependent row; the A02 chain at its
// start: 8 independent constraints), the text and JSON forms say the same, and a contradictory
// pin is a report that cannot run (not an exception) naming both rows.
#define BOOST_TEST_MODULE check
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <string>

#include "sim/case.hpp"
#include "sim/check.hpp"

using namespace pcsim;
using namespace pcsim::sim;
namespace fs = std::filesystem;

namespace {
fs::path case_file(const std::string& name) {
  return fs::path(PCSIM_SOURCE_DIR) / "cases" / (name + ".toml");
}
bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}
}  // namespace

BOOST_AUTO_TEST_CASE(parallelogram_with_a_third_crank_has_one_redundant_row) {
  const CheckReport r = check_case(load_case(case_file("parallelogram_third_crank")));
  BOOST_TEST(r.coordinates.size() == 12u);
  BOOST_TEST(r.active.size() == 12u);
  BOOST_REQUIRE(r.rank.has_value());
  BOOST_TEST(*r.rank == 11);
  BOOST_TEST(*r.dof == 1);
  BOOST_TEST(r.gruebler == 0);
  BOOST_TEST(*r.null_space_dimension == 1);
  BOOST_REQUIRE(r.redundant.size() == 1u);
  BOOST_TEST(r.redundant[0] == "M_coupler_y");
  BOOST_TEST(r.mass_positive_definite);
  BOOST_TEST(r.can_run);
  BOOST_TEST(r.reason.empty());
  BOOST_TEST(check_refusal(r).empty());
  const std::string text = format_check(r);
  BOOST_TEST(has(text, "rank of the active constraints at the initial state: 11 of 12\n"), text);
  BOOST_TEST(has(text, "redundant rows: 'M_coupler_y'"), text);
  BOOST_TEST(has(text, "  the case can run\n"), text);
  const nlohmann::json j = to_json(r);
  BOOST_TEST(j["rank"] == 11);
  BOOST_TEST(j["redundant"] == nlohmann::json::array({"M_coupler_y"}));
  BOOST_TEST(j["can_run"] == true);
  BOOST_TEST(j["correction"]["position"].is_number());
}

BOOST_AUTO_TEST_CASE(independent_chain_and_a_contradiction) {
  const Case c = load_case(case_file("fourbar_a02_N1"));
  const CheckReport ok = check_case(c);
  BOOST_TEST(*ok.rank == 8);
  BOOST_TEST(ok.active.size() == 8u);
  BOOST_TEST(ok.redundant.empty());
  BOOST_TEST(*ok.smallest_singular_value > 1e-6);
  BOOST_TEST(has(format_check(ok), "redundant rows: none\n"));

  const Case bad = load_case(case_file("fourbar_a02_N1"),
                             command_line_overrides({}, {"pin_shifted=xc0 - h*cos(tc0) - 0.1"}));
  const CheckReport r = check_case(bad);
  BOOST_TEST(!r.can_run);
  BOOST_TEST(has(r.reason, "'pin_shifted' contradicts 'A0_x'"), r.reason);
  BOOST_TEST(check_refusal(r) == "case 'fourbar_a02_N1' cannot run: " + r.reason);
  BOOST_TEST(!r.correction_pos.has_value());
  const std::string text = format_check(r);
  BOOST_TEST(!has(text, "can run"), text);
  BOOST_TEST(to_json(r)["correction"]["position"].is_null());
}
