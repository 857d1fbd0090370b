#include "formats/mesh/mesh_input.h"

#include <cmath>
#include <filesystem>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/mesh/gltf_reader.h"
#include "libvox/core/counted.h"
#include "libvox/core/error.h"
#include "libvox/core/utf8.h"

namespace vox {

bool isMeshFile(const std::string& path) { return fileKindOf(path) == FileKind::Mesh; }

void checkFinite(Mesh& mesh, const std::string& name, const MeshReadOptions& options, std::vector<std::string>& warnings) {
  std::vector<char> invalid(mesh.positions.size(), 0);
  size_t count = 0, first = 0;
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    for (double c : mesh.positions[i])
      if (!std::isfinite(c)) {
        if (!count) first = i;
        if (!invalid[i]) ++count;
        invalid[i] = 1;
      }
  if (!count) return;
  if (!options.dropInvalid)
    throwBadInput(name + ": " + counted(count, "vertex has", "vertices have") +
                      " NaN or infinite coordinates (the first is " + mesh.describeVertex(first, false) +
                      "); fix the file or drop their triangles",
                  Setting::DropInvalid);
  std::vector<bool> keep(mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    keep[t] = !invalid[tri[0]] && !invalid[tri[1]] && !invalid[tri[2]];
  }
  const size_t dropped = mesh.keepTriangles(keep);
  warnings.push_back(name + ": dropped " + counted(dropped, "triangle", "triangles") + " touching " +
                     counted(count, "vertex", "vertices") + " with NaN or infinite coordinates");
  // The vertices stay (unreferenced) so indices remain valid; make them finite.
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    if (invalid[i]) mesh.positions[i] = {0, 0, 0};
}

namespace {

/// The file's mesh as its reader gives it.
Mesh readAnyMesh(const std::string& path, const MeshReadOptions& options, std::vector<std::string>& warnings,
                 DeferredTextures* deferred) {
  if (hasExtension(path, ".gltf") || hasExtension(path, ".glb")) return readGltf(path, options, warnings, deferred);
  const FileView bytes(path);
  Mesh mesh;
  if (hasExtension(path, ".obj"))
    mesh = parseObj(bytes.data(), bytes.size(), path, options, warnings, std::filesystem::path(path).parent_path().string());
  else if (hasExtension(path, ".stl")) mesh = parseStl(bytes.data(), bytes.size(), path, options, warnings);
  else if (hasExtension(path, ".ply")) mesh = parsePly(bytes.data(), bytes.size(), path, options, warnings);
  else throwBadInput(path + ": not " + describe(FileKind::Mesh));
  mesh.filesRead.insert(mesh.filesRead.begin(), path);
  return mesh;
}

}  // namespace

Mesh readMeshFile(const std::string& path, const MeshReadOptions& options, std::vector<std::string>& warnings,
                  DeferredTextures* deferred) {
  Mesh mesh = readAnyMesh(path, options, warnings, deferred);
  // Names become class names, matched by --classes rules and written in JSON:
  // an OBJ's Windows-1252 "Mat\xe9riau" is "Matériau" from here on, and a
  // file named in Latin-1 names its parts in UTF-8.
  for (MeshMaterial& m : mesh.materials) m.name = utf8FromLegacy(m.name);
  for (MeshPart& part : mesh.parts) part.nodeName = utf8FromLegacy(part.nodeName), part.meshName = utf8FromLegacy(part.meshName);
  return mesh;
}

}  // namespace vox
