// The class table of a scene: what each class id means and how to draw it.
//
// Class ids are 1..255 (they must fit the `cls` byte of the summary atlas);
// id 0 is reserved for "empty" and never appears in a table. A table is kept
// sorted by id. Colours are 8-bit sRGB. The optional top/bottom/side colours are
// the per-face palette of the block-map format's block renderer (used by shaded
// renders). On disk: formats/scene/class_table_json.h.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "libvox/core/types.h"

namespace vox {

inline constexpr int kMaxClassId = 255;

struct FacePalette {
  Rgb8 top, bottom, side;
  bool operator==(const FacePalette&) const = default;
};

struct ClassInfo {
  uint8_t id = 0;       // 1..255
  std::string name;     // unique within a table, non-empty
  Rgb8 color;           // display colour (sRGB)
  std::optional<FacePalette> faces;
  bool operator==(const ClassInfo&) const = default;
};

class ClassTable {
 public:
  /// Adds a class. Throws vox::Error (BadInput) on id 0, a duplicate id or name,
  /// or an empty name; `context` prefixes the message (e.g. the file name).
  void add(ClassInfo info, const std::string& context = "class table");
  const ClassInfo* find(uint8_t id) const;
  const ClassInfo* findByName(const std::string& name) const;
  const std::vector<ClassInfo>& classes() const { return classes_; }
  size_t size() const { return classes_.size(); }
  bool operator==(const ClassTable&) const = default;

 private:
  std::vector<ClassInfo> classes_;  // sorted by id
};

/// The block-map format's materials in their order (Air = 0 is not in the
/// table): 1 Grass, 2 Dirt, 3 Stone, 4 Plank, 5 Snow, 6 Sand, 7 Water, each with
/// its top/bottom/side palette (the block renderer's float colours * 255,
/// rounded) and the top colour as the display colour.
ClassTable blockPalette();

/// "Air" and the block-map format's material names, index = class id.
const std::vector<std::string>& blockTypeNames();

/// Converts a [0,1] float colour to 8 bits: round(c * 255), clamped.
Rgb8 toRgb8(float r, float g, float b);

}  // namespace vox
