// A count and its noun for messages, in the singular where the count is one
// ("1 vertex", "2 vertices"); the CLI uses it too (voxcli::counted).
#pragma once

#include <cstdint>
#include <string>

namespace vox {

inline std::string counted(uint64_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace vox
