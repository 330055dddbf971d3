// Exceptions thrown at the outer boundary (case loading, CLI). Inside the numerical library,
// status is reported by value (Eigen's ComputationInfo style); these are for the user.
#pragma once

#include <stdexcept>
#include <string>

namespace pcsim {

/// Bad input from the user: a case file, a --set override, a CLI option. The message names
/// the file, the key and what was expected. The CLI exits with status 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The computation failed numerically (step size too small, singular matrix, ...). The
/// message says when (model time) and why. The CLI exits with status 3.
class NumericalError : public std::runtime_error {
 public:
  NumericalError(const std::string& what, double t) : std::runtime_error(what), t_(t) {}
  double time() const { return t_; }

 private:
  double t_;
};

}  // namespace pcsim
