// Which implementation of a numerical kernel runs: the Fortran-77 kernel through the
// ISO_C_BINDING bridge, or its C++ (Eigen) port. Both are kept so kernels can migrate one at
// a time while tests prove the two paths agree.
#pragma once

#include <optional>
#include <string_view>

namespace pcsim {

enum class Kernel { fortran, cpp };

/// "fortran" -> Kernel::fortran, "cpp" -> Kernel::cpp, anything else -> nullopt.
std::optional<Kernel> parse_kernel(std::string_view name);

/// The inverse of parse_kernel: "fortran" or "cpp".
const char* to_string(Kernel kernel);

}  // namespace pcsim
