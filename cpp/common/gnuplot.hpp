// Running gnuplot without a shell, and quoting text for its scripts. No text from input may
// execute anything: gnuplot runs by fork/exec with an argument vector (never std::system or
// popen), in the directory whose files it reads and writes, so a script names only fixed
// relative file names; titles and labels pass through gnuplot_quoted.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace pcsim {

/// `s` as a gnuplot single-quoted string literal, with no character that could end it: a single
/// quote becomes ’ and a backquote ‘ (gnuplot 5.4 mis-parses runs of doubled quotes: four
/// quotes end the string, so quotes are never passed through; backquotes are command
/// substitution in older gnuplots); control characters (a line break would end the command)
/// become spaces. Nothing else is special inside gnuplot's single quotes.
std::string gnuplot_quoted(const std::string& s);

/// A finite number as gnuplot reads it (%.17g); throws std::invalid_argument for NaN or inf,
/// which gnuplot would read as a variable name.
std::string gnuplot_number(double v);

/// The full path of `program` on PATH (an executable regular file), if any.
std::optional<std::filesystem::path> find_on_path(const std::string& program);

/// Runs `gnuplot` (found on PATH) with the working directory `dir`, feeding it `script` on its
/// standard input; its standard error goes to `stderr_file` (relative to `dir`) when not empty,
/// else to pcsim's. Returns gnuplot's exit status (-1 if it did not exit normally); throws
/// std::runtime_error if it cannot be started.
int run_gnuplot(const std::filesystem::path& dir, const std::string& script,
                const std::string& stderr_file = "");

}  // namespace pcsim
