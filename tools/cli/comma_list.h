// Option values that are comma lists: `--mode depth,class`, and the fixed
// tuples `--dims X,Y,Z`, `--eye X,Y,Z`, `--bounds`, `--region-box`,
// `--region`. Every one is split here, so all refuse the same mistakes the
// same way: an empty entry (a leading or trailing comma, two commas in a
// row, an empty value) is a usage error naming the option and the entry,
// never dropped (CLI11's own delimiter dropped it: `--mode depth,class,`
// rendered two modes without a word).
#pragma once

#include <string>
#include <vector>

namespace voxcli {

/// The entries of `text`, the value given to `option`, split at commas.
/// Throws vox::Error (Usage, exit 2) when an entry is empty:
/// "--mode depth,,class: entry 2 of 3 is empty (two commas in a row); expected
/// EXPECTED", where `expected` says what the option takes ("a comma list of
/// canonical, class, ...", "X,Y,Z (three positive integers)").
std::vector<std::string> splitCommaList(const std::string& text, const std::string& option,
                                        const std::string& expected);

}  // namespace voxcli
