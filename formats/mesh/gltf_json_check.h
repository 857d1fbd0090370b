// The glTF JSON checked against the ranges the glTF 2.0 specification gives,
// before tinygltf reads it: tinygltf coerces what it cannot represent (a
// negative byteOffset becomes 0, a count of 4e9 wraps to a negative int) and
// never checks indices between objects, so a malformed file would otherwise be
// read as something it does not say.
#pragma once

#include <string>
#include <string_view>

namespace vox {

/// How far from length 1 a node's rotation quaternion may be: the Khronos
/// validator's tolerance for a unit 4-vector (slightly more than 8-bit
/// quantization's error). The checks refuse a rotation beyond it; the reader
/// normalises one within it (as loaders do).
constexpr double kUnitQuaternionTolerance = 0.00769;

/// Checks the JSON of the .gltf file or the JSON chunk of the .glb file at
/// `path`: every extensionsRequired entry is one vox honours or one that cannot
/// change the voxels; accessor and bufferView offsets, lengths, strides and
/// counts are integers in their ranges; every index from one object to another
/// (scene, node -> mesh, primitive -> accessor/material, material -> texture,
/// texture -> image/sampler, bufferView -> buffer) names an existing object;
/// POSITION accessors are VEC3 of FLOAT (or of 8/16-bit integers with
/// KHR_mesh_quantization); a TRIANGLES primitive has a multiple of 3 indices
/// (or vertices); a node's matrix, translation, rotation and scale are arrays
/// of 16, 3, 4 and 3 numbers, the rotation within kUnitQuaternionTolerance of
/// unit length.
/// Throws BadInput naming the file and the element (e.g.
/// "accessors[3].byteOffset") on the first violation; JSON that does not parse
/// is left for tinygltf to report.
void checkGltfJson(const std::string& path);

/// The same on the file's bytes already in memory: `isBinary` says they are a
/// .glb container; `path` is used in messages only.
void checkGltfJsonBytes(std::string_view bytes, const std::string& path, bool isBinary);

/// The JSON text of a glTF file's bytes: all of a .gltf, or the JSON chunk of
/// a .glb (empty when the .glb header or first chunk is not well formed); a
/// view into `bytes`.
std::string_view gltfJsonText(std::string_view bytes, bool isBinary);

}  // namespace vox
