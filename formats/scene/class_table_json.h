// The class table as JSON: the one writer and the one reader of every file that
// carries a class table (formats/scene/SCENE.md, "The class table"):
//   * the scene metadata `vox:classes` (formats/scene/scene_meta.h),
//   * the page-file metadata `classes` (formats/pagefile/PAGEFILE.md),
//   * the `--classes FILE.json` rules file (formats/mesh/classes_json.h),
//   * `vox info --json`'s class list (the same entries, plus counts).
//
// An entry is {"id": 1..255, "name": "...", "color": [r, g, b]} with optional
// "top", "bottom" and "side" colours (the block palette of shaded renders).
// Colours are 8-bit sRGB. The face palette is all three keys or none: an entry
// with one or two of them is refused, never half-read.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "libvox/core/classes.h"

namespace vox {

/// The forms a class entry is read in. Stored is what classTableToJson writes
/// (every key required but the palette); HandWritten is the forgiving form of
/// a rules file a person writes: "id" defaults to the entry's position + 1,
/// "color" defaults to grey (128, 128, 128) and may be written "#rrggbb".
enum class ClassJsonForm { Stored, HandWritten };

/// One entry: {"id", "name", "color"[, "top", "bottom", "side"]}.
nlohmann::json classInfoToJson(const ClassInfo& info);

/// The table as a JSON array of entries sorted by id.
nlohmann::json classTableToJson(const ClassTable& table);

/// Reads entry `index` of a class array. `where` names the array in messages
/// ("scene.vdb: metadata 'vox:classes'"); errors name "<where>[index]" and the
/// key. Throws vox::Error (BadInput) on a missing or mistyped key, an id
/// outside 1..255, a colour that is not three integers 0..255, or a partial
/// face palette. Does not check uniqueness (ClassTable::add does).
ClassInfo classInfoFromJson(const nlohmann::json& entry, size_t index, ClassJsonForm form, const std::string& where);

/// Reads a whole class array into a table (ids and names unique). Throws
/// vox::Error (BadInput) naming `where` and the entry.
ClassTable classTableFromJson(const nlohmann::json& array, ClassJsonForm form, const std::string& where);

}  // namespace vox
