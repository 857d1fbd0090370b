// vox diff of JSON files (reports, touched sets, info output, camera files):
// vox::diffJson with --rel-tolerance and the ignored keys.
#include <iostream>
#include <sstream>

#include "formats/core/file_util.h"
#include "formats/core/json_diff.h"
#include "formats/core/json_text.h"
#include "libvox/core/number_text.h"
#include "tools/cli/cli.h"
#include "tools/cmds/diff_common.h"

namespace voxcli {

int diffJsonFiles(const DiffOptions& o) {
  const nlohmann::json a = vox::parseJsonDocument(vox::readFileBytes(o.a), o.a);
  const nlohmann::json b = vox::parseJsonDocument(vox::readFileBytes(o.b), o.b);
  vox::JsonDiffOptions jo;
  jo.relTolerance = o.relTolerance;
  if (o.noDefaultIgnores) jo.ignoreKeys.clear();
  for (const std::string& k : o.ignoreKeys) jo.ignoreKeys.push_back(k);
  const vox::JsonDiff d = vox::diffJson(a, b, jo);
  auto valueJson = [](const vox::JsonValueDiff& v) {
    nlohmann::json j = {{"pointer", v.pointer}, {"a", v.a}, {"b", v.b}};
    if (v.relativeError) j["relative_error"] = *v.relativeError;
    return j;
  };
  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& v : d.differences) list.push_back(valueJson(v));
    nlohmann::json j = {{"kind", "json"},
                        {"a", o.a},
                        {"b", o.b},
                        {"same", d.same()},
                        {"values_compared", d.valuesCompared},
                        {"values_differing", d.differing},
                        {"keys_ignored", d.ignored},
                        {"ignore_patterns", jo.ignoreKeys},
                        {"rel_tolerance", o.relTolerance},
                        {"differences", list}};
    if (!d.differences.empty()) j["first_difference"] = valueJson(d.differences[0]);
    if (d.worstNumber) j["worst_number"] = valueJson(*d.worstNumber);
    std::cout << vox::jsonText(j, 2) << "\n";
  } else {
    std::ostringstream s;
    s << (d.same() ? "same" : "DIFFERENT") << ": JSON, " << counted(d.valuesCompared, "value", "values")
      << " compared, " << d.differing << " differ (relative tolerance " << vox::shortestText(o.relTolerance) << "; "
      << counted(d.ignored, "ignored key", "ignored keys") << " skipped)\n";
    for (const auto& v : d.differences) {
      s << "  " << pointerText(v.pointer) << ": " << v.a << " vs " << v.b;
      if (v.relativeError) s << " (relative error " << *v.relativeError << ")";
      s << "\n";
    }
    if (d.differing > d.differences.size()) s << "  ... " << (d.differing - d.differences.size()) << " more\n";
    if (d.worstNumber && d.differing > 1)
      s << "  worst number: " << pointerText(d.worstNumber->pointer) << ": " << d.worstNumber->a << " vs " << d.worstNumber->b
        << " (relative error " << *d.worstNumber->relativeError << ")\n";
    std::cout << s.str();
  }
  return d.same() ? kExitOk : kExitCheckFailed;
}

}  // namespace voxcli
