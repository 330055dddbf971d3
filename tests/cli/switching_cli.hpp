// Shared by the switching CLI tests: the common helpers (tests/support/cli_util.hpp) and pcsim()
// that runs the executable from the source tree with an environment.
#pragma once

#include <string>

#include "../support/cli_util.hpp"

namespace switching_cli {

namespace fs = std::filesystem;
using pcsim_test::exe;
using pcsim_test::read;
using pcsim_test::Result;
using pcsim_test::TempDir;

/// Runs `env ENV... pcsim ARGS` from the source tree.
inline Result pcsim(const std::string& args, const std::string& env = "") {
  return pcsim_test::sh((env.empty() ? "" : "env " + env + " ") + "'" + exe() + "' " + args,
                        PCSIM_SOURCE_DIR);
}

}  // namespace switching_cli
