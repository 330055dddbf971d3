// Running gnuplot without a shell, and quoting text for its scripts. No text from input may
// execute anything: gnuplot runs by fork/exec with an argument vector (never std::system or
// popen), in the directory whose files it reads and writes, so a script names only fixed
// relative file names; titles and labels pass through gnuplot_quoted.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

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

/// Runs `program` (a full path) with the arguments `args` (an argument vector: fork and execv,
/// never a shell) in the working directory `dir`; `feed` is called once with a writer to the
/// program's standard input (it returns false once the program stops reading) and may stream
/// any amount through it. Standard error goes to `stderr_file` (relative to `dir`) when not
/// empty. Returns the exit status (-1 if the program did not exit normally; 1 if it stopped
/// reading but exited 0); throws std::runtime_error if it cannot be started. gnuplot and
/// ffmpeg (pcsim animate --video) run through it.
int run_program(const std::filesystem::path& program, const std::vector<std::string>& args,
                const std::filesystem::path& dir,
                const std::function<void(const std::function<bool(const char*, std::size_t)>&)>& feed,
                const std::string& stderr_file = "");

/// Runs `gnuplot` (found on PATH) with the working directory `dir`, feeding it `script` on its
/// standard input; its standard error goes to `stderr_file` (relative to `dir`) when not empty,
/// else to pcsim's. Returns gnuplot's exit status (-1 if it did not exit normally); throws
/// std::runtime_error if it cannot be started.
int run_gnuplot(const std::filesystem::path& dir, const std::string& script,
                const std::string& stderr_file = "");

}  // namespace pcsim
