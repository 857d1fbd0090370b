// Texture images a bake reads row by row instead of taking them whole from
// mesh.textures (VoxelizeSettings::textureRows): after the surface pass's
// geometry it knows every textured piece's texel, sorts the pieces into bands
// of rows and reads each image top to bottom once, a band at a time, so the
// image is never held whole (formats/mesh/deferred_textures.h supplies glTF
// colour images this way; libvox decodes nothing itself).
//
// Thread-safety: open() may be called from several threads at once for
// different images; a reader is used by one thread.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace vox {

/// Rows per band: the bake holds a band of an image, the row after it and row
/// 0 at a time (a band of a 2048-wide image and its next row: 136 KB, within
/// the L2 cache its pieces' samples read from).
inline constexpr uint32_t kTextureBandRows = 16;

/// One image, read top to bottom.
class TextureRowReader {
 public:
  virtual ~TextureRowReader() = default;
  virtual uint32_t width() const = 0;
  virtual uint32_t height() const = 0;
  /// The next `count` rows (8-bit RGBA, width x 4 bytes each, row 0 the
  /// image's top row) into `rgba`; 1 <= count <= the rows not read yet. Throws vox::Error naming the image when
  /// its data do not decode.
  virtual void read(uint8_t* rgba, uint32_t count) = 0;
};

/// The images of a mesh whose textures have no pixels yet (width 0 in
/// mesh.textures): image i's pixels are those of the mesh textures
/// texturesOf(i) (several textures may sample one image).
class TextureRowSource {
 public:
  virtual ~TextureRowSource() = default;
  virtual size_t images() const = 0;
  virtual const std::vector<size_t>& texturesOf(size_t image) const = 0;
  /// The width and height image `image`'s header announces, before any pixel
  /// is decoded (the bake places its pieces' texels with it); 0 x 0 when the
  /// header does not read (open() then throws).
  virtual std::array<uint32_t, 2> size(size_t image) const = 0;
  /// Starts reading image `image` (once per image). Throws vox::Error naming
  /// the image when it cannot be decoded.
  virtual std::unique_ptr<TextureRowReader> open(size_t image) = 0;
};

}  // namespace vox
