// Registration of pcsim subcommands. Each cpp/cli/cmd_*.cpp file adds its subcommand(s) to the
// CLI11 app with a static registration object, so commands are added without editing main.cpp:
//
//   static void setup(CLI::App& app) { auto* sub = app.add_subcommand("run", "..."); ... }
//   static const bool registered = pcsim::cli::register_command(10, &setup);
//
// A subcommand callback does the work and reports failure by throwing pcsim::InputError
// (exit 2), pcsim::NumericalError (exit 3) or any other std::exception (exit 1); main prints
// the one-line reason as "pcsim: error: <what>".
#pragma once

namespace CLI { class App; }

namespace pcsim::cli {

using CommandSetup = void (*)(CLI::App& app);

/// Registers a subcommand setup function; `order` fixes the order in --help. Returns true.
bool register_command(int order, CommandSetup setup);

}  // namespace pcsim::cli
