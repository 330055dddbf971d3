// The engine's statuses (SimulationStatus, ModelIssue) come from one table each in
// mech/status.hpp (name, message), expanded into the enum, to_string() and message() the way
// the ODE status table is. This test walks each table: every enumerator has its own name and
// its own message, and the functions return exactly the table's entries.
#define BOOST_TEST_MODULE mech_status_tables
#include <boost/test/unit_test.hpp>

#include <set>
#include <string>
#include <vector>

#include "mech/status.hpp"

using namespace pcsim::mech;

namespace {

struct Row {
  std::string name, message;
};

template <class E>
void check_table(const std::vector<std::pair<E, Row>>& table) {
  std::set<std::string> names, messages;
  for (const auto& [value, row] : table) {
    BOOST_TEST(std::string(to_string(value)) == row.name);
    BOOST_TEST(std::string(message(value)) == row.message);
    BOOST_TEST(!row.message.empty(), row.name);
    BOOST_TEST(names.insert(row.name).second, "name '" << row.name << "' used twice");
    BOOST_TEST(messages.insert(row.message).second, "message '" << row.message << "' used twice");
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(simulation_status_names_and_messages_are_distinct_and_from_the_table) {
  std::vector<std::pair<SimulationStatus, Row>> t;
#define PCSIM_ROW(name, text) t.push_back({SimulationStatus::name, Row{#name, text}});
  PCSIM_SIMULATION_STATUS_TABLE(PCSIM_ROW)
#undef PCSIM_ROW
  BOOST_TEST(t.size() == 8u);
  check_table(t);
  // The summary's failure status is the message (a CLI contract).
  BOOST_TEST(std::string(message(SimulationStatus::integration_failed)) == "integration failed");
}

BOOST_AUTO_TEST_CASE(model_issue_names_and_messages_are_distinct_and_from_the_table) {
  std::vector<std::pair<ModelIssue, Row>> t;
#define PCSIM_ROW(name, text) t.push_back({ModelIssue::name, Row{#name, text}});
  PCSIM_MODEL_ISSUE_TABLE(PCSIM_ROW)
#undef PCSIM_ROW
  BOOST_TEST(t.size() == 8u);
  check_table(t);
}
