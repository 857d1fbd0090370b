// Which class each triangle of a mesh votes for.
//
// Rules match glob patterns (fnmatch(3): *, ?, [...]) against a triangle's
// material name, mesh name or node name (MeshPart); a pattern without a field
// prefix matches any of the three. Classes are tried in table order, and a
// class's patterns in their order: the first match wins. Triangles no rule
// matches go to the default class, or are an error naming the triangle's
// material, mesh and node when there is none.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "libvox/core/classes.h"
#include "libvox/mesh/mesh.h"

namespace vox {

struct ClassRule {
  enum class Field { Any, Material, Mesh, Node };
  Field field = Field::Any;
  std::string pattern;
  uint8_t classId = 0;
};

struct ClassMapping {
  ClassTable table;
  std::vector<ClassRule> rules;  // in priority order
  std::optional<uint8_t> defaultClass;
  /// classPerMaterial only: the class of each material (index = material).
  /// Empty for a rules file.
  std::vector<uint8_t> materialClass;
};

/// The class of triangles that have no material (readers give them an
/// unnamed, white, untextured material): named "default" and drawn grey, so a
/// plain mesh shows up on a white background.
inline constexpr const char* kDefaultClassName = "default";
inline constexpr Rgb8 kDefaultClassColor{150, 150, 150};  // #969696

/// Without a mapping file: one class per material name, in order of first
/// appearance (ids 1..). Materials that share a name share a class (coloured
/// with the first one's base colour factor in sRGB). An unnamed material is
/// "material N" (N = its index), except the unnamed white untextured material
/// readers give triangles without one, which is the class kDefaultClassName in
/// kDefaultClassColor (all such materials share it). More than 255 classes is
/// an error.
ClassMapping classPerMaterial(const Mesh& mesh, const std::string& meshName);

/// The class id of every triangle. Throws vox::Error (BadInput) for a triangle
/// no rule matches when there is no default class.
std::vector<uint8_t> assignClasses(const Mesh& mesh, const ClassMapping& mapping);

bool globMatch(const std::string& pattern, const std::string& text);

}  // namespace vox
