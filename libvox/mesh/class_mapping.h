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
};

/// Without a mapping file: one class per material (ids 1.. in material order,
/// named after the material or "material N", coloured with its base colour
/// factor in sRGB). More than 255 materials is an error.
ClassMapping classPerMaterial(const Mesh& mesh, const std::string& meshName);

/// The class id of every triangle. Throws vox::Error (BadInput) for a triangle
/// no rule matches when there is no default class.
std::vector<uint8_t> assignClasses(const Mesh& mesh, const ClassMapping& mapping);

bool globMatch(const std::string& pattern, const std::string& text);

}  // namespace vox
