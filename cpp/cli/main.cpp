// pcsim: the command line. Subcommands, and the applications compiled in, register themselves
// (see commands.hpp and cpp/cli/CMakeLists.txt).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <utility>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "common/files.hpp"

namespace pcsim::cli {

namespace {
std::vector<std::pair<int, CommandSetup>>& registry() {
  static std::vector<std::pair<int, CommandSetup>> commands;
  return commands;
}
}  // namespace

bool register_command(int order, CommandSetup setup) {
  registry().emplace_back(order, setup);
  return true;
}

}  // namespace pcsim::cli

int main(int argc, char** argv) {
  CLI::App app{
      "pcsim: constrained mechanical systems by the principle of compatibility, with the "
      "reaction forces computed directly"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "pcsim 0.1.0");
  auto commands = pcsim::cli::registry();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& c : commands) c.second(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const pcsim::InputError& e) {
    std::fprintf(stderr, "pcsim: error: %s\n", e.what());
    return 2;
  } catch (const pcsim::NumericalError& e) {
    std::fprintf(stderr, "pcsim: error: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcsim: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
