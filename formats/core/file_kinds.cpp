#include "formats/core/file_kinds.h"

#include <array>

namespace vox {

namespace {
struct KindEntry {
  FileKind kind;
  const char* description;
  std::vector<std::string_view> extensions;
};

const std::array<KindEntry, 5>& table() {
  static const std::array<KindEntry, 5> t{{
      {FileKind::Mesh, "a mesh", {".obj", ".ply", ".stl", ".gltf", ".glb"}},
      {FileKind::BlockMap, "a block map", {".json"}},
      {FileKind::Vdb, "an OpenVDB scene or grid", {".vdb"}},
      {FileKind::PageFile, "a page file", {".vpk"}},
      {FileKind::Image, "an image (atlas, bitmap or render)", {".png", ".exr"}},
  }};
  return t;
}
}  // namespace

bool hasExtension(const std::string& path, std::string_view ext) {
  if (path.size() < ext.size()) return false;
  for (size_t i = 0; i < ext.size(); ++i) {
    char c = path[path.size() - ext.size() + i];
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    if (c != ext[i]) return false;
  }
  return true;
}

const std::vector<std::string_view>& extensionsOf(FileKind kind) {
  for (const KindEntry& e : table())
    if (e.kind == kind) return e.extensions;
  static const std::vector<std::string_view> none;
  return none;
}

std::string describe(FileKind kind) {
  for (const KindEntry& e : table()) {
    if (e.kind != kind) continue;
    std::string s = std::string(e.description) + " (";
    for (size_t i = 0; i < e.extensions.size(); ++i) s += (i ? " " : "") + std::string(e.extensions[i]);
    return s + ")";
  }
  return "?";
}

std::optional<FileKind> fileKindOf(const std::string& path) {
  for (const KindEntry& e : table())
    for (std::string_view ext : e.extensions)
      if (hasExtension(path, ext)) return e.kind;
  return std::nullopt;
}

bool isDemoName(const std::string& input) { return input.rfind(kDemoPrefix, 0) == 0; }

}  // namespace vox
