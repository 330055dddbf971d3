// The project's one number formatter: shortest round-trip decimals (std::to_chars) for every
// number written to a file or a table, and significant-digit text for messages and reports.
#pragma once

#include <string>

namespace pcsim {

/// Shortest decimal text that parses back to exactly v ("0.3", "280", "1e-05", "inf", "nan").
std::string format_number(double v);

/// Appends format_number(v) to out without a temporary string.
void append_number(std::string& out, double v);

/// The room write_number needs at p (the longest number is 24 characters,
/// "-2.2250738585072014e-308").
constexpr int kMaxNumberChars = 48;

/// Writes format_number(v) at p (room for kMaxNumberChars) and returns the end, with no
/// allocation (the time-series writer's hot path: it formats whole rows into one buffer).
char* write_number(char* p, double v);

/// A number as a CSV field: format_number(v) if v is finite, else an empty field. A value that
/// is not defined (f* = |R_s|/R_u in flight, a difference of a missing margin, an output divided
/// by zero) is written as nothing, never as "nan", "-nan" or "inf", which CSV readers parse
/// differently or not at all (README, "Output"). Every CSV writer of pcsim writes numbers so.
std::string csv_number(double v);

/// Appends csv_number(v) to out.
void append_csv_number(std::string& out, double v);

/// Writes csv_number(v) at p (room for kMaxNumberChars) and returns the end.
char* write_csv_number(char* p, double v);

/// v with `digits` significant digits (printf %.*g), for messages and reports.
std::string format_significant(double v, int digits = 6);

/// A count with its noun in the right number: counted(1, "step") = "1 step", counted(3, "step")
/// = "3 steps" (plural: the noun + "s" unless given). Messages say counts through this, so no
/// message reads "1 steps".
std::string counted(long long n, const std::string& noun, const std::string& plural = "");

}  // namespace pcsim
