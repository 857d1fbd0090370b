// glTF images decoded once each, in parallel, and only when the voxels need
// them: tinygltf is told to keep each image's encoded bytes instead of decoding
// it while it parses (one after the other, every image, normal and
// metallic-roughness maps too); afterwards the images that materials' colour
// textures use are decoded (formats/mesh/texture_image.h: JPEG by
// libjpeg-turbo, WebP by libwebp, PNG by stb_image) to 8-bit RGBA on TBB's threads.
// The result does not depend on the thread count: each image is decoded on its own.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "formats/mesh/deferred_textures.h"
#include "formats/mesh/mesh_input.h"

namespace tinygltf {
class Model;
class TinyGLTF;
}  // namespace tinygltf

namespace vox {

/// Every image's encoded bytes as tinygltf found them, by image index: a
/// bufferView's bytes are not copied but seen where they are, in the model's
/// buffer (valid while the model lives: a textured .glb's images are most of
/// its bytes, and copying them cost as much fresh memory again); a data URI's
/// or an external file's, which tinygltf frees after handing them over, are
/// kept here.
struct EncodedImages {
  std::vector<std::string> owned;             // data URIs and external files
  std::vector<std::string_view> inModel;      // bufferView images: their bytes in model.buffers
  // 0: tinygltf never delivered the image (an external file it could not
  // read); 1: its bytes are in `owned`; 2: in the model (`inModel`).
  std::vector<char> received;

  std::string_view bytes(size_t i) const { return received[i] == 2 ? inModel[i] : std::string_view(owned[i]); }
  bool isInModel(size_t i) const { return received[i] == 2; }
  void resize(size_t n) {
    owned.resize(n);
    inModel.resize(n);
    received.resize(n, 0);
  }
};

/// Makes `loader` store each image's bytes in `images` instead of decoding it.
void deferImageDecoding(tinygltf::TinyGLTF& loader, EncodedImages& images);

/// Decodes the images i with needed[i] (those colour textures use) into
/// model.images[i] (image = RGBA8 rows, top row first; width, height,
/// component 4, bits 8) in parallel, and frees their encoded bytes. An image
/// that does not decode is an error naming it (`path`, image index, uri), or
/// with options.ignoreMissingMaterials a warning (its textures are left out).
void decodeImages(tinygltf::Model& model, EncodedImages& images, const std::vector<char>& needed,
                  const std::string& path, const MeshReadOptions& options, std::vector<std::string>& warnings);

/// The same images left to `deferred` (formats/mesh/deferred_textures.h),
/// which the bake decodes: their encoded bytes move to it (those in the
/// model's buffers stay there, and `model` is kept alive until they are
/// read, when they are at least half of the buffers' bytes; else they are
/// copied), and model.images stays undecoded. Returns each image's index in
/// `deferred`, or -1 for the images not decoded (not needed, or never received).
std::vector<int> decodeImagesLater(const std::shared_ptr<tinygltf::Model>& model, EncodedImages& images,
                                   const std::vector<char>& needed, const std::string& path, DeferredTextures& deferred);

}  // namespace vox
