#include "libvox/mesh/class_mapping.h"
#include "libvox/core/color.h"

#include <fnmatch.h>

#include <algorithm>
#include <cmath>

#include "libvox/core/error.h"

namespace vox {

bool globMatch(const std::string& pattern, const std::string& text) {
  return fnmatch(pattern.c_str(), text.c_str(), 0) == 0;
}

namespace {

// The material readers give triangles without one (formats/mesh): no name,
// white, no texture.
bool isNoMaterial(const MeshMaterial& m) {
  return m.name.empty() && m.texture < 0 && m.baseColorFactor[0] == 1 && m.baseColorFactor[1] == 1 &&
         m.baseColorFactor[2] == 1;
}

}  // namespace

ClassMapping classPerMaterial(const Mesh& mesh, const std::string& meshName) {
  ClassMapping m;
  // Names first, so the class count (not the material count) is what must fit.
  std::vector<std::string> nameOf(mesh.materials.size());
  std::vector<std::string> distinct;
  for (size_t i = 0; i < mesh.materials.size(); ++i) {
    const MeshMaterial& mat = mesh.materials[i];
    nameOf[i] = isNoMaterial(mat) ? kDefaultClassName : mat.name.empty() ? "material " + std::to_string(i) : mat.name;
    if (std::find(distinct.begin(), distinct.end(), nameOf[i]) == distinct.end()) distinct.push_back(nameOf[i]);
  }
  if (distinct.size() > size_t(kMaxClassId))
    throwBadInput(meshName + ": " + std::to_string(distinct.size()) +
                  " distinct material names, but a scene holds at most 255 classes; map them to fewer classes with "
                  "class rules",
                  Setting::ClassRules);
  m.materialClass.resize(mesh.materials.size());
  for (size_t i = 0; i < mesh.materials.size(); ++i) {
    if (const ClassInfo* c = m.table.findByName(nameOf[i])) {
      m.materialClass[i] = c->id;
      continue;
    }
    const MeshMaterial& mat = mesh.materials[i];
    ClassInfo c;
    c.id = uint8_t(m.table.size() + 1);
    c.name = nameOf[i];
    c.color = isNoMaterial(mat) ? kDefaultClassColor
                                : Rgb8{linearToSrgb8(mat.baseColorFactor[0]), linearToSrgb8(mat.baseColorFactor[1]),
                                       linearToSrgb8(mat.baseColorFactor[2])};
    m.materialClass[i] = c.id;
    m.table.add(c, meshName);
  }
  return m;
}

std::vector<uint8_t> assignClasses(const Mesh& mesh, const ClassMapping& mapping) {
  std::vector<uint8_t> out(mesh.triangles.size(), 0);
  const bool perMaterial = !mapping.materialClass.empty();
  // Decide once per (material, part) pair: meshes have few of them.
  std::vector<std::vector<int>> memo;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uint32_t mat = mesh.triangleMaterial.empty() ? 0 : mesh.triangleMaterial[t];
    const uint32_t part = mesh.trianglePart.empty() ? 0 : mesh.trianglePart[t];
    if (perMaterial) {
      if (mat >= mapping.materialClass.size())
        throw Error(ErrorKind::Internal, "triangle " + std::to_string(t) + " has material " + std::to_string(mat) +
                                             " beyond the mesh's " + std::to_string(mapping.materialClass.size()));
      out[t] = mapping.materialClass[mat];
      continue;
    }
    if (memo.size() <= mat) memo.resize(mat + 1);
    if (memo[mat].size() <= part) memo[mat].resize(part + 1, -1);
    int& cls = memo[mat][part];
    if (cls < 0) {
      const std::string matName = mat < mesh.materials.size() ? mesh.materials[mat].name : "";
      const std::string meshName = part < mesh.parts.size() ? mesh.parts[part].meshName : "";
      const std::string nodeName = part < mesh.parts.size() ? mesh.parts[part].nodeName : "";
      cls = 0;
      for (const ClassRule& r : mapping.rules) {
        const bool hit = (r.field == ClassRule::Field::Any || r.field == ClassRule::Field::Material) && globMatch(r.pattern, matName)
                      ? true
                      : ((r.field == ClassRule::Field::Any || r.field == ClassRule::Field::Mesh) && globMatch(r.pattern, meshName)) ||
                            ((r.field == ClassRule::Field::Any || r.field == ClassRule::Field::Node) && globMatch(r.pattern, nodeName));
        if (hit) {
          cls = r.classId;
          break;
        }
      }
      if (cls == 0 && mapping.defaultClass) cls = *mapping.defaultClass;
      if (cls == 0)
        throwBadInput("triangle " + std::to_string(t) + " (material '" + matName + "', mesh '" + meshName + "', node '" +
                      nodeName + "') matches no class rule; add a rule or a \"default\" class to the class rules",
                  Setting::ClassRules);
    }
    out[t] = uint8_t(cls);
  }
  return out;
}

}  // namespace vox
