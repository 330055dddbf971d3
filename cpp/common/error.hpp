// Exceptions thrown at the outer boundary (case loading, output files, CLI): one hierarchy under
// pcsim::Error. Inside the numerical library and the engine, status is reported by value
// (Eigen's ComputationInfo style); the case layer and above turn it into these for the user.
#pragma once

#include <stdexcept>
#include <string>

namespace pcsim {

/// Every error pcsim reports to its user. The CLI exits with the status of the kind below
/// (1 for an error of no other kind).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input from the user: a case file, a --set override, a CLI option. The message names
/// the file, the key and what was expected. The CLI exits with status 2.
class InputError : public Error {
 public:
  using Error::Error;
};

/// The computation failed numerically (step size too small, singular matrix, ...). The
/// message says when (model time) and why. The CLI exits with status 3.
class NumericalError : public Error {
 public:
  NumericalError(const std::string& what, double t) : Error(what), t_(t) {}
  double time() const { return t_; }

 private:
  double t_;
};

/// An output file or directory could not be written; the message names the path and the
/// system's reason (errno text). The CLI exits with status 1.
class IoError : public Error {
 public:
  using Error::Error;
};

}  // namespace pcsim
