// Mesh files -> vox::Mesh. Every reader records the files it read (for
// dependency files), converts sRGB-encoded colours to linear, and throws vox::Error
// (BadInput) naming the file and the element (line, face, vertex, accessor).
//
//   .obj  with .mtl (usemtl, Kd, map_Kd; polygons triangulated as
//         formats/mesh/polygon_triangulation.h says, negative indices)
//   .ply  1.0, ASCII and binary (both endiannesses), vertex colours, any index types
//   .stl  ASCII (every solid of the file) and binary
// Every reader records in Mesh::vertexRuns how its file numbers its vertices,
// for messages that name one.
//   .gltf / .glb   see formats/mesh/gltf_reader.h
// Extensions are matched case-insensitively.
#pragma once

#include <string>
#include <vector>

#include "libvox/mesh/mesh.h"

namespace vox {

struct MeshReadOptions {
  /// Drop triangles that touch a vertex with a NaN or infinite coordinate, and
  /// OBJ/PLY faces of fewer than 3 vertices (counted in `warnings`), instead
  /// of refusing the file.
  bool dropInvalid = false;
  /// OBJ: an `mtllib` file or a `map_Kd` texture that does not exist is
  /// reported in `warnings` (materials keep their names, untextured) instead of
  /// refusing the file. Off by default: a missing file is an error naming it.
  bool ignoreMissingMaterials = false;
};

class DeferredTextures;

/// Reads any supported mesh file by extension. Non-fatal notes (skipped
/// primitives, dropped triangles) are appended to `warnings`. `deferred`:
/// glTF colour textures are left undecoded to it, for the bake to read by rows
/// (formats/mesh/deferred_textures.h); other formats ignore it.
Mesh readMeshFile(const std::string& path, const MeshReadOptions& options, std::vector<std::string>& warnings,
                  DeferredTextures* deferred = nullptr);

/// True for the extensions readMeshFile accepts.
bool isMeshFile(const std::string& path);

// Parsers over bytes in memory (the file readers and the fuzz targets use them).
/// OBJ: the numbers of "v" and "f" lines are read in parallel, in chunks of
/// about `chunkBytes` of whole lines (on TBB's threads); the result, warnings
/// and errors do not depend on the chunks or the threads (tests split files
/// into tiny chunks to check it).
Mesh parseObj(const char* data, size_t size, const std::string& name, const MeshReadOptions& options,
              std::vector<std::string>& warnings, const std::string& baseDir = "",
              size_t chunkBytes = size_t(1) << 18);
Mesh parseStl(const char* data, size_t size, const std::string& name, const MeshReadOptions& options,
              std::vector<std::string>& warnings);
Mesh parsePly(const char* data, size_t size, const std::string& name, const MeshReadOptions& options,
              std::vector<std::string>& warnings);

/// Removes triangles touching non-finite vertices when options.dropInvalid, or
/// throws naming `where(vertex)` and the count otherwise.
void checkFinite(Mesh& mesh, const std::string& name, const MeshReadOptions& options,
                 std::vector<std::string>& warnings);

}  // namespace vox
