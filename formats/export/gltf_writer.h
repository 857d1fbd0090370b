// glTF 2.0 files of block meshes (libvox/core/block_mesh.h): `.glb` (one
// binary file) or `.gltf` (JSON text plus a `.bin` buffer beside it). Layout in
// docs/export.md.
//
// One mesh, one node, one primitive per group of quads (all the blocks, or one
// per class), each with its material. Per primitive, one interleaved vertex
// buffer view (byte stride 44: POSITION, NORMAL, COLOR_0 as float VEC3 (linear
// RGB), TEXCOORD_0 as float VEC2) and, when indexed, one index buffer view
// (UNSIGNED_SHORT when the primitive has at most 65535 vertices, else
// UNSIGNED_INT). Not indexed: six vertices per quad, the corners of triangles
// 0-1-2 and 0-2-3 (the block renderer's vertex stream). Indexed: four vertices
// per quad and six indices; no vertex is shared between quads, because two
// quads never agree on a corner's texture coordinates (docs/export.md).
//
// Written by hand rather than through tinygltf: tinygltf's model owns every
// buffer as a std::vector, so a mesh would be copied in full (twice for .glb)
// before a byte is written; here the vertices are produced straight into the
// file in blocks, and the JSON is nlohmann's (sorted keys), so the same mesh
// gives the same bytes.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "libvox/core/block_mesh.h"

namespace vox {

struct GltfMaterial {
  std::string name;
  std::optional<uint8_t> classId;  // recorded in the material's extras
};

struct GltfPrimitive {
  std::span<const BlockQuad> quads;
  size_t material = 0;  // index into GltfScene::materials
};

struct GltfScene {
  std::string name;       // of the mesh and its node
  std::string generator;  // asset.generator
  GridFrame frame;        // world placement of index space (voxelSize > 0)
  std::vector<GltfMaterial> materials;
  std::vector<GltfPrimitive> primitives;  // empty primitives are skipped
  bool indexed = false;
  /// Threads for writing: with more than one, quads are expanded into
  /// vertices on a second thread while the previous batch is written. The
  /// bytes do not depend on it.
  unsigned threads = 1;
};

struct GltfWriteResult {
  uint64_t vertices = 0, indices = 0, triangles = 0;
  uint64_t bufferBytes = 0;       // of the binary buffer
  uint64_t unindexedBufferBytes = 0;  // what the buffer would be without indices (for the report)
  uint64_t fileBytes = 0;         // .glb, or .gltf + .bin
};

/// The bytes the writers hold besides the scene's quads while they write:
/// two batches of vertices (one being written, the next expanded beside it)
/// and, when indexed, a batch of indices. For memory guards.
uint64_t gltfWriteBufferBytes(bool indexed);

/// Writes `scene` as a .glb to `path`. Throws vox::Error (Io) when writing fails.
GltfWriteResult writeGlb(const GltfScene& scene, const std::string& path);

/// Writes `scene` as .gltf JSON to `path` and its buffer to `binPath`, which
/// the JSON names by `binName` (the .bin's file name, beside the .gltf) as a
/// relative URI, percent-encoded (formats/core/uri_segment.h): "a#b.bin" is
/// written "a%23b.bin". With no quads at all, no buffer is written and
/// `binPath` is left alone.
GltfWriteResult writeGltf(const GltfScene& scene, const std::string& path, const std::string& binPath,
                          const std::string& binName);

}  // namespace vox
