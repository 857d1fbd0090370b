// Comparing two JSON documents (reports, touched sets, camera files, info
// output) value by value, for `vox diff` (docs/diff.md).
//
// Walk: depth first, object keys in sorted order, array elements by index; a
// difference is named by its JSON pointer (RFC 6901: "/levels/2/iou").
//   * numbers are equal when a == b or |a - b| <= relTolerance * max(|a|, |b|)
//     (integers of both documents are compared exactly when relTolerance is 0);
//   * other values (strings, booleans, null) must be equal, and types must match
//     (a number is not a string);
//   * a key present on one side only, or an array element past the other's end,
//     is a difference whose missing side is "(absent)".
// Keys matching an ignore pattern are skipped wherever they appear, with what
// is under them. Patterns are key names with '*' matching any run of
// characters. defaultIgnoredJsonKeys() are the keys whose values change from
// run to run without the result changing: timings and rates ("seconds",
// "*_seconds", "*_per_second", "*_per_s"), the thread count, and paths as the
// user typed them ("argv", "inputs", "outputs", "scene", "file", "path"), and
// a run report's memory estimate and limit ("memory": they include the
// process's resident memory when it checked, and the machine's size).
//
// Thread safety: pure functions.
#pragma once

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

namespace vox {

const std::vector<std::string>& defaultIgnoredJsonKeys();

/// True when `key` matches `pattern` ('*' = any run of characters).
bool jsonKeyMatches(const std::string& pattern, const std::string& key);

struct JsonDiffOptions {
  double relTolerance = 0;
  std::vector<std::string> ignoreKeys = defaultIgnoredJsonKeys();
  size_t maxListed = 20;  // differences kept in `differences` (all are counted)
};

struct JsonValueDiff {
  std::string pointer;  // "" is the whole document
  std::string a, b;     // the values as compact JSON, or "(absent)"
  std::optional<double> relativeError;  // numbers: |a - b| / max(|a|, |b|)
};

struct JsonDiff {
  uint64_t valuesCompared = 0;  // leaves (scalars) compared
  uint64_t differing = 0;
  uint64_t ignored = 0;         // keys skipped by a pattern
  std::vector<JsonValueDiff> differences;  // the first maxListed, in walk order
  std::optional<JsonValueDiff> worstNumber;  // the largest relative error among differing numbers
  bool same() const { return differing == 0; }
};

JsonDiff diffJson(const nlohmann::json& a, const nlohmann::json& b, const JsonDiffOptions& options = {});

/// Parses `text` as JSON; throws vox::Error (BadInput) naming `name`, the line
/// and column of the fault.
nlohmann::json parseJsonDocument(const std::string& text, const std::string& name);

}  // namespace vox
