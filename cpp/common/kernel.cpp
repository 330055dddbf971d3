#include "common/kernel.hpp"

namespace pcsim {

std::optional<Kernel> parse_kernel(std::string_view name) {
  if (name == "fortran") return Kernel::fortran;
  if (name == "cpp") return Kernel::cpp;
  return std::nullopt;
}

const char* to_string(Kernel kernel) {
  return kernel == Kernel::fortran ? "fortran" : "cpp";
}

}  // namespace pcsim
