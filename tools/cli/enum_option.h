// Options whose values are names ("--fill surface|solid"), parsed into enums by
// a CLI11 transformer, so commands compare enums, never strings.
//
// The name table is the one place a command spells its values: the option's
// help shows the names and the default (the name of the enum's value when the
// option is added), a name not in the table is a usage error listing them, and
// reports print values back through nameOf().
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace voxcli {

/// The command-line names of an enum's values, in the order help lists them.
template <typename E>
using EnumNames = std::vector<std::pair<std::string, E>>;

/// The name of `value` in `names` ("" when absent).
template <typename E>
std::string nameOf(const EnumNames<E>& names, E value) {
  for (const auto& [n, v] : names)
    if (v == value) return n;
  return "";
}

/// Adds option `flag` that takes one of `names` into `value`. Exact names only
/// (case matters); anything else fails parsing: "--fill: expected surface|solid, got 'x'".
template <typename E>
CLI::Option* addEnumOption(CLI::App& app, const std::string& flag, E& value, const EnumNames<E>& names,
                           const std::string& help) {
  static_assert(std::is_enum_v<E>);
  std::string list;
  for (const auto& [n, v] : names) list += (list.empty() ? "" : "|") + n;
  // CLI11 reads an enum as its underlying integer: the transformer turns the
  // name into that number (and refuses numbers, which are not names).
  auto toNumber = [names, list](std::string& input) -> std::string {
    for (const auto& [n, v] : names)
      if (input == n) {
        input = std::to_string(static_cast<std::underlying_type_t<E>>(v));
        return {};
      }
    return "expected " + list + ", got '" + input + "'";
  };
  return app.add_option(flag, value, help)
      ->transform(CLI::Validator(toNumber, "", ""))
      ->type_name(list)
      ->default_str(nameOf(names, value));
}

}  // namespace voxcli
