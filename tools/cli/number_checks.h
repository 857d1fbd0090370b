#pragma once
// Validators for floating-point options. CLI11's PositiveNumber and Range
// compare with < and >, which NaN passes, so "--voxel-size nan" would slip
// through to the default; these reject NaN and infinities by name.

#include <CLI/CLI.hpp>
#include <cmath>
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

}  // namespace voxcli
