// `vox info` for the JSON files vox writes: touched sets (render-canonical
// --touched, formats/image/RENDER.md), run reports (--report of every
// command) and atlas sidecars (build-atlas's STEM.atlas.json). Both are summarised for people; --json prints the file's content
// with "file" and "kind" added.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace voxcli {

/// What kind of vox JSON `doc` is: "touched", "report", "atlas_sidecar"
/// (build-atlas's STEM.atlas.json), or "" when none.
std::string voxJsonKind(const nlohmann::json& doc);

/// Describes a touched set / a report on stdout. Return the exit code.
int infoTouchedSet(const std::string& path, bool json);
int infoReport(const std::string& path, const nlohmann::json& doc, bool json);
int infoAtlasSidecar(const std::string& path, bool json);

}  // namespace voxcli
