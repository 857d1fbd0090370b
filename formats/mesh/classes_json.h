// The --classes FILE.json mapping of material, mesh and node names to classes.
//
//   { "classes": [
//       {"id": 1, "name": "roof", "color": [180, 60, 50], "match": ["*roof*", "material:Tiles*"]},
//       {"id": 2, "name": "wall", "color": "#c8c8c8",     "match": ["node:house/*"],
//        "top": [..], "bottom": [..], "side": [..]} ],
//     "default": "wall" }
//
// * Each entry is a class table entry in its hand-written form
//   (formats/scene/class_table_json.h, ClassJsonForm::HandWritten): id 1..255
//   (optional: the position in the array + 1), name unique, colour as
//   [r, g, b] 0..255 or "#rrggbb" (sRGB, optional: grey); the top/bottom/side
//   face palette all three or none.
// * match: glob patterns, optionally prefixed with "material:", "mesh:" or
//   "node:" to look at one name only (class_mapping.h says how they are tried).
// * default: the name of the class for triangles no pattern matches; without
//   it such triangles are an error.
// * Any other key, in the file or an entry, is refused by name (BadInput): a
//   misspelt "match" or "default" would otherwise map nothing without a word.
#pragma once

#include <string>

#include "libvox/mesh/class_mapping.h"

namespace vox {

/// Throws vox::Error (BadInput) naming the file and the entry.
ClassMapping readClassMapping(const std::string& path);
ClassMapping parseClassMapping(const std::string& text, const std::string& path);

}  // namespace vox
