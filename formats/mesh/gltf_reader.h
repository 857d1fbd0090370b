// glTF 2.0 (.gltf with external or data-URI buffers and images, and .glb) to a
// vox::Mesh, through tinygltf for the container and our own accessor reader
// (byteStride, normalized integers, sparse accessors, KHR_mesh_quantization).
//
// * The default scene (else scene 0, else every root node), node transforms
//   (matrix or TRS) composed down the hierarchy, world-space positions.
// * Primitives in modes TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN, indexed or
//   not; other modes are skipped with a warning.
// * Materials: baseColorFactor, baseColorTexture (its image decoded to RGBA8,
//   its sampler's wrap modes and mag filter, its texCoord set, its
//   KHR_texture_transform as MeshMaterial::uvTransform), or KHR_materials_pbrSpecularGlossiness's
//   diffuseFactor and diffuseTexture; COLOR_0 (vec3/vec4, float or normalized)
//   multiplies in. Only those images are decoded, once each, in parallel
//   (formats/mesh/gltf_images.h), or during the caller's bake with a
//   DeferredTextures (formats/mesh/deferred_textures.h).
// * EXT_mesh_gpu_instancing: one copy of the node's mesh per instance.
// * Parts: one per (node, primitive's mesh): node name path "a/b/c", mesh name.
// * KHR_draco_mesh_compression: the primitive's Draco data decoded
//   (formats/mesh/gltf_draco.h); a corrupt one is refused naming the primitive.
// * EXT_meshopt_compression: compressed bufferViews decoded
//   (formats/mesh/gltf_meshopt.h); a corrupt one is refused naming the view.
// * NaN or infinite positions: refused naming the accessor and the count, or
//   dropped (MeshReadOptions::dropInvalid).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "formats/mesh/deferred_textures.h"
#include "formats/mesh/mesh_input.h"

namespace vox {

/// `deferred`: when given (and without options.ignoreMissingMaterials), the
/// colour textures' images are left undecoded to it, for the bake to read by
/// rows (formats/mesh/deferred_textures.h); the mesh's textures then have no
/// pixels.
Mesh readGltf(const std::string& path, const MeshReadOptions& options, std::vector<std::string>& warnings,
              DeferredTextures* deferred = nullptr);

/// The same from the file's bytes already in memory (the fuzz target's entry;
/// readGltf reads the file and calls it). `isBinary`: the bytes are a .glb
/// container, else .gltf JSON. `path` names the input in messages, and its
/// directory is where external buffers and images are looked for.
Mesh readGltfMemory(std::string_view bytes, const std::string& path, bool isBinary, const MeshReadOptions& options,
                    std::vector<std::string>& warnings, DeferredTextures* deferred = nullptr);

}  // namespace vox
