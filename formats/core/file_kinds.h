// The kinds of file voxbake reads and writes, recognised by extension in one
// table, so that every command accepts the same names and every message that
// lists them lists them all (case-insensitive: model.OBJ is a mesh).
//
// Extensions say what a file claims to be; readers still check the content
// (magic numbers) and refuse a file that is not what its name says.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vox {

enum class FileKind {
  Mesh,       // .obj .ply .stl .gltf .glb: triangle meshes (formats/mesh)
  BlockMap,   // .json given as a voxelize input: the block-map format
  Vdb,        // .vdb: a scene, a pyramid, or a foreign OpenVDB grid
  PageFile,   // .vpk: chunked page file (formats/pagefile)
  Image,      // .png .exr: atlases, bitmaps and renders
};

/// The extensions of `kind`, lower case with the dot, in the order messages list them.
const std::vector<std::string_view>& extensionsOf(FileKind kind);

/// "a mesh (.obj .ply .stl .gltf .glb)", for messages.
std::string describe(FileKind kind);

/// The kind whose extension `path` ends with (case-insensitive), or nullopt.
/// A .json file is a BlockMap only where a command takes block maps as input.
std::optional<FileKind> fileKindOf(const std::string& path);

/// True when `path` ends with `extension` (".vdb"), ignoring case.
bool hasExtension(const std::string& path, std::string_view extension);

/// The input built into voxbake ("demo:hamlet"), recognised by its prefix.
inline constexpr std::string_view kDemoPrefix = "demo:";
bool isDemoName(const std::string& input);

}  // namespace vox
