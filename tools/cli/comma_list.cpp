#include "tools/cli/comma_list.h"

#include "libvox/core/error.h"

namespace voxcli {

std::vector<std::string> splitCommaList(const std::string& text, const std::string& option,
                                        const std::string& expected) {
  if (text.empty()) vox::throwUsage(option + " '': an empty value; expected " + expected);
  std::vector<std::string> entries;
  size_t pos = 0;
  while (true) {
    const size_t comma = text.find(',', pos);
    entries.push_back(text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  for (size_t i = 0; i < entries.size(); ++i) {
    if (!entries[i].empty()) continue;
    const char* why = i == 0 ? "a leading comma" : i + 1 == entries.size() ? "a trailing comma" : "two commas in a row";
    vox::throwUsage(option + " " + text + ": entry " + std::to_string(i + 1) + " of " + std::to_string(entries.size()) +
                    " is empty (" + why + "); expected " + expected);
  }
  return entries;
}

}  // namespace voxcli
