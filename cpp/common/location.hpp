// How a message names the input it refuses: a file's path, or "<case>" for a case in memory.
#pragma once

#include <filesystem>
#include <string>

namespace pcsim {

/// The name messages give an input file: its path, or "<case>" if it has none (a case built
/// in memory).
inline std::string input_location(const std::filesystem::path& file) {
  return file.empty() ? std::string("<case>") : file.string();
}

}  // namespace pcsim
