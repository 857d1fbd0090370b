#include "formats/core/json_diff.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "formats/core/json_input.h"
#include "libvox/core/error.h"

namespace vox {

const std::vector<std::string>& defaultIgnoredJsonKeys() {
  static const std::vector<std::string> keys{"seconds", "*_seconds", "*_per_second", "*_per_s", "threads",
                                             "argv",    "inputs",    "outputs",      "scene",   "file",
                                             "path",    "memory"};
  return keys;
}

bool jsonKeyMatches(const std::string& pattern, const std::string& key) {
  // Iterative glob with '*' only (backtracking to the last star).
  size_t p = 0, k = 0, star = std::string::npos, mark = 0;
  while (k < key.size()) {
    if (p < pattern.size() && pattern[p] == '*') {
      star = p++, mark = k;
    } else if (p < pattern.size() && pattern[p] == key[k]) {
      ++p, ++k;
    } else if (star != std::string::npos) {
      p = star + 1, k = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

namespace {

std::string escapeToken(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

struct Walker {
  const JsonDiffOptions& o;
  JsonDiff& d;

  bool ignored(const std::string& key) const {
    for (const std::string& p : o.ignoreKeys)
      if (jsonKeyMatches(p, key)) return true;
    return false;
  }

  void note(const std::string& ptr, const std::string& a, const std::string& b, std::optional<double> rel) {
    ++d.differing;
    JsonValueDiff v{ptr, a, b, rel};
    if (rel && (!d.worstNumber || *rel > *d.worstNumber->relativeError)) d.worstNumber = v;
    if (d.differences.size() < o.maxListed) d.differences.push_back(std::move(v));
  }

  static uint64_t leaves(const nlohmann::json& j) {
    if (j.is_object() || j.is_array()) {
      uint64_t n = 0;
      for (const auto& e : j) n += leaves(e);
      return n;
    }
    return 1;
  }

  void absent(const std::string& ptr, const nlohmann::json* a, const nlohmann::json* b) {
    d.valuesCompared += leaves(a ? *a : *b);
    note(ptr, a ? a->dump() : "(absent)", b ? b->dump() : "(absent)", std::nullopt);
  }

  void walk(const std::string& ptr, const nlohmann::json& a, const nlohmann::json& b) {
    if (a.is_object() && b.is_object()) {
      auto ia = a.begin(), ib = b.begin();  // both sorted by key
      while (ia != a.end() || ib != b.end()) {
        int cmp = ia == a.end() ? 1 : ib == b.end() ? -1 : ia.key().compare(ib.key());
        const std::string& key = cmp <= 0 ? ia.key() : ib.key();
        if (ignored(key)) {
          ++d.ignored;
        } else {
          const std::string child = ptr + "/" + escapeToken(key);
          if (cmp == 0) walk(child, ia.value(), ib.value());
          else if (cmp < 0) absent(child, &ia.value(), nullptr);
          else absent(child, nullptr, &ib.value());
        }
        if (cmp <= 0) ++ia;
        if (cmp >= 0) ++ib;
      }
      return;
    }
    if (a.is_array() && b.is_array()) {
      const size_t n = std::max(a.size(), b.size());
      for (size_t i = 0; i < n; ++i) {
        const std::string child = ptr + "/" + std::to_string(i);
        if (i < a.size() && i < b.size()) walk(child, a[i], b[i]);
        else if (i < a.size()) absent(child, &a[i], nullptr);
        else absent(child, nullptr, &b[i]);
      }
      return;
    }
    ++d.valuesCompared;
    if (a.is_number() && b.is_number()) {
      if (a.is_number_integer() && b.is_number_integer()) {
        // Exactly, past 2^53 too.
        auto wide = [](const nlohmann::json& j) {
          return j.is_number_unsigned() ? __int128(j.get<uint64_t>()) : __int128(j.get<int64_t>());
        };
        if (wide(a) == wide(b)) return;
        if (o.relTolerance == 0) {  // past 2^53 the doubles below may be equal
          const double x = a.get<double>(), y = b.get<double>();
          const double scale = std::max(std::fabs(x), std::fabs(y));
          note(ptr, a.dump(), b.dump(), scale > 0 ? std::fabs(x - y) / scale : 0.0);
          return;
        }
      }
      const double x = a.get<double>(), y = b.get<double>();
      if (x == y) return;
      const double scale = std::max(std::fabs(x), std::fabs(y));
      const double rel = std::fabs(x - y) / scale;  // scale > 0 since x != y
      if (rel <= o.relTolerance) return;
      note(ptr, a.dump(), b.dump(), std::isnan(rel) ? std::numeric_limits<double>::infinity() : rel);
      return;
    }
    if (a.is_object() || a.is_array() || b.is_object() || b.is_array() || a != b)
      note(ptr, a.dump(), b.dump(), std::nullopt);
  }
};

}  // namespace

JsonDiff diffJson(const nlohmann::json& a, const nlohmann::json& b, const JsonDiffOptions& options) {
  JsonDiff d;
  Walker{options, d}.walk("", a, b);
  return d;
}

nlohmann::json parseJsonDocument(const std::string& text, const std::string& name) {
  try {
    return parseJsonInput(text, name);
  } catch (const nlohmann::json::exception& e) {
    // A parse_error's e.what() carries "line L, column C" of the fault; a number
    // past double's range is an out_of_range (406), not a parse_error.
    std::string what = e.what();
    const size_t at = what.find("parse error");
    throw Error(ErrorKind::BadInput, name + ": not valid JSON: " + (at == std::string::npos ? what : what.substr(at)));
  }
}

}  // namespace vox
