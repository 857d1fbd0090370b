#include "libvox/core/classes.h"

#include <algorithm>
#include <cmath>

#include "libvox/core/error.h"

namespace vox {

std::string toString(const Dims& d) {
  return std::to_string(d.x) + " x " + std::to_string(d.y) + " x " + std::to_string(d.z);
}
std::string toString(const Coord3& c) {
  // Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string s(1, '(');
  s.append(std::to_string(c.u)).append(", ").append(std::to_string(c.v)).append(", ");
  s.append(std::to_string(c.w)).append(")");
  return s;
}

void ClassTable::add(ClassInfo info, const std::string& context) {
  if (info.id == 0)
    throwBadInput(context + ": class '" + info.name + "' has id 0, which means empty; use 1..255");
  if (info.name.empty())
    throwBadInput(context + ": class " + std::to_string(info.id) + " has an empty name");
  if (find(info.id))
    throwBadInput(context + ": class id " + std::to_string(info.id) + " is used twice ('" +
                  find(info.id)->name + "' and '" + info.name + "')");
  if (findByName(info.name))
    throwBadInput(context + ": class name '" + info.name + "' is used twice");
  auto at = std::lower_bound(classes_.begin(), classes_.end(), info.id,
                             [](const ClassInfo& c, uint8_t id) { return c.id < id; });
  classes_.insert(at, std::move(info));
}

const ClassInfo* ClassTable::find(uint8_t id) const {
  auto at = std::lower_bound(classes_.begin(), classes_.end(), id,
                             [](const ClassInfo& c, uint8_t i) { return c.id < i; });
  return at != classes_.end() && at->id == id ? &*at : nullptr;
}

const ClassInfo* ClassTable::findByName(const std::string& name) const {
  for (const ClassInfo& c : classes_)
    if (c.name == name) return &c;
  return nullptr;
}

Rgb8 toRgb8(float r, float g, float b) {
  auto q = [](float c) {
    float s = std::round(std::clamp(c, 0.0f, 1.0f) * 255.0f);
    return static_cast<uint8_t>(s);
  };
  return {q(r), q(g), q(b)};
}

const std::vector<std::string>& blockTypeNames() {
  static const std::vector<std::string> names = {"Air",  "Grass", "Dirt", "Stone",
                                                 "Plank", "Snow", "Sand", "Water"};
  return names;
}

ClassTable blockPalette() {
  // The block renderer's palette (top, bottom, side) as it gives it, floats in [0, 1].
  static const float kPalette[7][3][3] = {
      {{0.34f, 0.68f, 0.36f}, {0.40f, 0.30f, 0.16f}, {0.45f, 0.58f, 0.30f}},  // Grass
      {{0.42f, 0.32f, 0.20f}, {0.38f, 0.26f, 0.16f}, {0.40f, 0.30f, 0.18f}},  // Dirt
      {{0.58f, 0.60f, 0.64f}, {0.55f, 0.57f, 0.60f}, {0.56f, 0.58f, 0.62f}},  // Stone
      {{0.78f, 0.68f, 0.50f}, {0.72f, 0.60f, 0.42f}, {0.74f, 0.63f, 0.45f}},  // Plank
      {{0.92f, 0.94f, 0.96f}, {0.90f, 0.92f, 0.94f}, {0.88f, 0.90f, 0.93f}},  // Snow
      {{0.88f, 0.82f, 0.60f}, {0.86f, 0.78f, 0.56f}, {0.87f, 0.80f, 0.58f}},  // Sand
      {{0.22f, 0.40f, 0.66f}, {0.20f, 0.34f, 0.60f}, {0.20f, 0.38f, 0.64f}},  // Water
  };
  ClassTable table;
  for (int m = 0; m < 7; ++m) {
    auto c = [&](int slot) { return toRgb8(kPalette[m][slot][0], kPalette[m][slot][1], kPalette[m][slot][2]); };
    ClassInfo info;
    info.id = static_cast<uint8_t>(m + 1);
    info.name = blockTypeNames()[m + 1];
    info.color = c(0);
    info.faces = FacePalette{c(0), c(1), c(2)};
    table.add(std::move(info), "block palette");
  }
  return table;
}

}  // namespace vox
