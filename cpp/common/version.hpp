// The version of this pcsim build: the project version and the git commit of its sources
// ("0.1.0 (abc123def456-dirty)"), for records that must name the code that made them.
#pragma once

namespace pcsim {
const char* version_string();
}  // namespace pcsim
