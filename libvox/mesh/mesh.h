// A triangle mesh as the voxelizer consumes it: every input format (glTF, OBJ,
// PLY, STL) is flattened into one of these by formats/, with node transforms
// already applied, so libvox never sees file formats.
//
// Units: positions are in the source's world units (after node transforms).
// Colours are linear-light (sRGB-encoded inputs are decoded by the readers).
// Ownership: plain values; a Mesh owns its texture pixels.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vox {

/// A decoded RGBA8 texture (sRGB-encoded texels as stored in the file) with its
/// sampler state (glTF semantics).
struct MeshTexture {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, row 0 = top of the image (v = 0 in glTF)
  enum class Wrap { Repeat, ClampToEdge, MirroredRepeat } wrapS = Wrap::Repeat, wrapT = Wrap::Repeat;
  bool nearest = false;       // magFilter NEAREST; otherwise bilinear
  std::string source;         // file name or "data URI"/"bufferView N", for messages
};

struct MeshMaterial {
  std::string name;                            // material name ("" if unnamed)
  std::array<float, 4> baseColorFactor{1, 1, 1, 1};  // linear RGBA
  int texture = -1;                            // index into Mesh::textures, or -1
  int texCoordSet = 0;                         // which UV set the texture uses (0 or 1)
  /// Where the texture is sampled, from the interpolated texture coordinates
  /// (s, t) (glTF conventions: t = 0 at the top row):
  /// s' = T[0] s + T[1] t + T[2], t' = T[3] s + T[4] t + T[5]. The identity
  /// unless a format places a texture by material: glTF's
  /// KHR_texture_transform, an MTL map's -o and -s. The UVs stay as read (an
  /// OBJ vertex may be shared by faces of materials placed differently).
  std::array<double, 6> uvTransform{1, 0, 0, 0, 1, 0};
  bool placesTexture() const { return uvTransform != std::array<double, 6>{1, 0, 0, 0, 1, 0}; }
};

/// A named group of triangles (glTF node/mesh, OBJ object/group), for class
/// mapping by name (class rules' globs match material, mesh or node names).
struct MeshPart {
  std::string nodeName;  // glTF node name path ("root/house/door") or OBJ "o"/"g" name
  std::string meshName;  // glTF mesh name, or the file name for single-mesh formats
};

/// Where a run of vertices came from, so that a message names a vertex as its
/// file does. Mesh vertex i (firstVertex <= i < the next run's firstVertex) is
/// "`file`: `what` N`note`", N = firstNumber + (i - firstVertex), or
/// Mesh::fileVertex[i] where that is not 0.
struct MeshVertexRun {
  size_t firstVertex = 0;
  std::string file;
  std::string what;         // "vertex", "mesh 'M' primitive 0, accessor 3 (POSITION) element"
  int64_t firstNumber = 1;
  std::string note;         // how the file counts them: " (counted from 0, as its faces count them)"
};

struct Mesh {
  std::vector<std::array<double, 3>> positions;
  std::vector<std::array<uint32_t, 3>> triangles;  // indices into positions (and per-vertex arrays)
  std::vector<uint32_t> triangleMaterial;          // per triangle, index into materials
  std::vector<uint32_t> trianglePart;              // per triangle, index into parts
  std::vector<std::array<float, 2>> uv0, uv1;      // per vertex, empty if absent
  std::vector<std::array<float, 4>> colors;        // per vertex linear RGBA (COLOR_0, PLY), empty if absent
  std::vector<MeshMaterial> materials;             // at least one when triangles exist
  std::vector<MeshTexture> textures;
  std::vector<MeshPart> parts;                     // at least one when triangles exist
  std::vector<std::string> filesRead;              // every file read (buffers, textures), for dependency files
  std::vector<MeshVertexRun> vertexRuns;           // in vertex order, for messages; none: vertices counted from 1
  std::vector<uint32_t> fileVertex;                // per vertex, its number in its file where that is not its run's
                                                   // count (OBJ: the "v" it came from), 0 elsewhere; empty if none

  size_t triangleCount() const { return triangles.size(); }
  bool hasColor() const;  // true when any material has a texture, a non-white factor, or vertex colours
  /// Appends `other` (indices, materials, textures, parts and vertex runs are re-based).
  void append(const Mesh& other);
  /// Vertex `i` as its file names it ("model.obj: vertex 12 (...)", without
  /// "model.obj: " when not `withFile`), for messages.
  std::string describeVertex(size_t i, bool withFile = true) const;
  /// Keeps, in order, the triangles t for which keep[t] is true, with their
  /// material and part and, when given, the caller's own per-triangle values
  /// (`alongside`, one per triangle). Vertices stay, so indices remain valid.
  /// Returns how many triangles were dropped.
  size_t keepTriangles(const std::vector<bool>& keep, std::vector<uint8_t>* alongside = nullptr);
};

}  // namespace vox
