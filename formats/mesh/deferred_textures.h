// Texture images decoded by the bake, row by row, instead of while the file
// is read: a photo-like 2048^2 JPEG costs about 28 ms of one core to decode
// (libjpeg-turbo's entropy decoding, whatever its options) and 16 MB as RGBA,
// and on the VMs we measure on faulting that memory in cost about as much
// again. A mesh read with a DeferredTextures (readMeshFile's last argument)
// comes back at once with its textures named, sampled and wrapped as the file
// says but without pixels (width = height = 0); the bake
// (VoxelizeSettings::textureRows, libvox/mesh/texture_rows.h) reads each image
// once after its geometry, a band of rows at a time, one image per task, so a
// JPEG texture is never held whole (PNG, WebP and the other formats are
// decoded whole when opened: formats/mesh/texture_image.h).
//
// The result does not depend on it: the same pixels, and an image that does
// not decode is the same error (message, exit 3) as when it is decoded while
// the file is read, for the first such image in index order. Only glTF colour
// textures are deferred (OBJ map_Kd files are decoded while read), and never
// with ignoreMissingMaterials, whose warning for an undecodable image must be
// known when the read returns.
//
// Thread-safety: open() may run concurrently for different images, and the
// readers on the threads that opened them; the other members are called from
// one thread while no reader is in use.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "libvox/mesh/texture_rows.h"

namespace vox {

class DeferredTextures final : public TextureRowSource {
 public:
  DeferredTextures();
  ~DeferredTextures() override;
  DeferredTextures(const DeferredTextures&) = delete;
  DeferredTextures& operator=(const DeferredTextures&) = delete;

  // TextureRowSource: the images, the mesh textures each is the pixels of,
  // their header sizes, and reading one (throws vox::Error (BadInput,
  // Setting::IgnoreMissingMaterials) naming the image when it does not
  // decode, as a read that decodes first does).
  size_t images() const override;
  const std::vector<size_t>& texturesOf(size_t image) const override;
  std::array<uint32_t, 2> size(size_t image) const override;
  std::unique_ptr<TextureRowReader> open(size_t image) override;

  /// Decodes, and drops, every image no reader was opened for (a bake that
  /// never needed them, such as a region that no triangle reaches), and
  /// throws the error of the first image in index order that does not
  /// decode, read or not: a file with an undecodable colour image is refused
  /// whatever the bake needed.
  void finish();

  /// The memory reading the images takes at the most, for the bake's memory
  /// estimate: `threads` images read at once, each its band of rows and the
  /// decoder's own rows (JPEG), or its whole pixels (formats decoded whole).
  uint64_t readingBytes(unsigned threads) const;

  /// One warning per image whose data were damaged but decoded
  /// (damagedImageWarning: the same words as when images are decoded while
  /// the file is read), in index order; complete after finish().
  std::vector<std::string> warnings() const;

  /// The images decoded, and the seconds their decoding took (elapsed on the
  /// threads that read them, summed over images); complete after finish().
  size_t decodedImages() const;
  double decodeSeconds() const;

  // For the readers (formats/mesh/gltf_images.cpp): one image each.
  /// Adds an image to decode: its encoded bytes, and `name` for the error
  /// message ("model.glb: image 3 'wood.jpg'"). Returns its index.
  size_t addImage(std::string bytes, std::string name);
  /// The same for bytes that stay where they are, in memory `owner` keeps
  /// alive (a glTF model's buffer): no copy; `owner` is let go once the image
  /// has been read.
  size_t addImage(std::shared_ptr<const void> owner, std::string_view bytes, std::string name);
  /// Texture `meshTexture` of the mesh being read uses image `image`'s pixels.
  void addTexture(size_t image, size_t meshTexture);

 private:
  struct Image;
  class Reader;
  size_t add(std::unique_ptr<Image> image);
  std::vector<std::unique_ptr<Image>> images_;
};

}  // namespace vox
