// LcpStatus comes from one table (lcp/lcp.hpp: name, message), expanded into the enum,
// to_string() and message() the way the ODE status table is. Every enumerator has its own name
// and its own message, and the functions return exactly the table's entries.
#define BOOST_TEST_MODULE lcp_status_table
#include <boost/test/unit_test.hpp>

#include <set>
#include <string>

#include "lcp/lcp.hpp"

using namespace pcsim::lcp;

BOOST_AUTO_TEST_CASE(lcp_status_names_and_messages_are_distinct_and_from_the_table) {
  std::set<std::string> names, messages;
  int rows = 0;
#define PCSIM_ROW(name, text)                                                         \
  ++rows;                                                                             \
  BOOST_TEST(std::string(to_string(LcpStatus::name)) == #name);                      \
  BOOST_TEST(std::string(message(LcpStatus::name)) == text);                         \
  BOOST_TEST(names.insert(#name).second, "name '" #name "' used twice");             \
  BOOST_TEST(messages.insert(text).second, "message of '" #name "' used twice");
  PCSIM_LCP_STATUS_TABLE(PCSIM_ROW)
#undef PCSIM_ROW
  BOOST_TEST(rows == 5);
  // The names are what messages and the switching tests print.
  BOOST_TEST(std::string(to_string(LcpStatus::no_solution)) == "no_solution");
}
