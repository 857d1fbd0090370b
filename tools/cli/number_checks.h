#pragma once
// Validators for floating-point options. CLI11's PositiveNumber and Range
// compare with < and >, which NaN passes, so "--voxel-size nan" would slip
// through to the default; these reject NaN and infinities by name. Their
// messages print bounds with %g: CLI11's NonNegativeNumber printed its upper
// bound, DBL_MAX, as a 309-digit number.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>

namespace voxcli {

/// A finite number > 0 (sizes, scales, tolerances that must not vanish).
inline const CLI::Validator FinitePositive(
    [](std::string& text) -> std::string {
      double v = 0;
      if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || !(v > 0))
        return "expected a finite number > 0, got '" + text + "'";
      return {};
    },
    "FINITE>0");

/// A finite number >= 0 (tolerances, thresholds that may be zero).
inline const CLI::Validator FiniteNonNegative(
    [](std::string& text) -> std::string {
      double v = 0;
      if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || !(v >= 0))
        return "expected a finite number >= 0, got '" + text + "'";
      return {};
    },
    "FINITE>=0");

/// Any finite number (thresholds on signed values).
inline const CLI::Validator Finite(
    [](std::string& text) -> std::string {
      double v = 0;
      if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v))
        return "expected a finite number, got '" + text + "'";
      return {};
    },
    "FINITE");

/// A finite number in [lo, hi] (fractions, percentages).
inline CLI::Validator FiniteInRange(double lo, double hi) {
  auto g = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  const std::string range = "[" + g(lo) + ", " + g(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || !(v >= lo && v <= hi))
          return "expected a finite number in " + range + ", got '" + text + "'";
        return {};
      },
      "FINITE in " + range);
}

/// A number >= 0 or inf: a threshold whose default, infinity, means "off"
/// (`vox diff --hardfail`), so inf may be given as well; never NaN.
inline const CLI::Validator NonNegativeOrInfinity(
    [](std::string& text) -> std::string {
      double v = 0;
      if (!CLI::detail::lexical_cast(text, v) || std::isnan(v) || !(v >= 0))
        return "expected a number >= 0 (or inf, off), got '" + text + "'";
      return {};
    },
    ">=0 or inf");

}  // namespace voxcli
