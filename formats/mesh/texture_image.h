// Texture images of meshes (OBJ map_Kd files, glTF colour textures) decoded to
// 8-bit RGBA: the one decoder both mesh readers use.
//
// JPEG goes through libjpeg-turbo (Debian's libjpeg62-turbo): its SIMD
// decoder is 2-3x faster than stb_image's on the large JPEG textures
// photogrammetry and generated models carry, and decoding was most of the
// cost a textured bake adds. It decodes with the exact integer IDCT
// (JDCT_ISLOW) and integer upsampling, so the pixels are the same on every
// CPU. WebP (EXT_texture_webp) goes through libwebp; PNG through the
// libdeflate fast path (formats/mesh/png_fast_decode.h: about 1.5-3x faster,
// the same pixels) where it applies, else, with the other formats stb_image
// reads, through stb_image.
//
// Thread-safe: each call decodes on the calling thread with its own state.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace vox {

struct TextureImage {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, row 0 = the image's top row
  /// Not empty: the data are damaged (a JPEG cut short or with corrupt
  /// entropy data, a PNG chunk whose CRC fails) but decoded as far as they
  /// go, as image viewers and stb_image show them; the first damage found.
  /// Callers warn with damagedImageWarning.
  std::string warning;
};

/// The largest image decoded, in pixels (a 16384 x 16384 texture: 1 GiB as RGBA);
/// a header announcing more is refused before any pixel memory is taken.
inline constexpr uint64_t kMaxTexturePixels = uint64_t(1) << 28;

/// Decodes `bytes` (the whole encoded file). On failure returns false and sets
/// `why` to a short reason ("not a PNG, JPEG or WebP", "a CMYK JPEG", "truncated
/// JPEG data", ...); `out` is then unspecified.
bool decodeTextureImage(std::string_view bytes, TextureImage& out, std::string& why);

/// An image read top to bottom, some rows at a time, so that a bake can take
/// its texels band by band without holding the whole image
/// (formats/mesh/deferred_textures.h): a JPEG is decoded row by row (a
/// 2048^2 texture is 16 MB as RGBA, and on the VMs we measure on fresh memory
/// costs about as much to fault in as the decoding itself); the other formats
/// (PNG, WebP, ...) are decoded whole by open() and handed out from there.
/// The pixels and the errors are decodeTextureImage's, which reads through it.
///
/// Thread-safety: one decoder per thread; decoders are independent.
class TextureRowDecoder {
 public:
  TextureRowDecoder();
  ~TextureRowDecoder();
  TextureRowDecoder(const TextureRowDecoder&) = delete;
  TextureRowDecoder& operator=(const TextureRowDecoder&) = delete;

  /// Reads the header (and decodes a format read whole). `bytes` must outlive
  /// the decoder. False with `why` set as decodeTextureImage's.
  bool open(std::string_view bytes, std::string& why);
  uint32_t width() const;
  uint32_t height() const;
  /// The rows handed out so far.
  uint32_t rowsRead() const;
  /// TextureImage::warning for what was decoded so far ("" while the data are sound).
  const std::string& warning() const;
  /// The next `count` rows (RGBA8, width x 4 bytes each, no padding) into
  /// `rgba`; count <= height - rowsRead(). The read that returns the last row
  /// also reads the end of the data. False with `why` set on a decoding error
  /// (the decoder can then only be destroyed).
  bool read(uint8_t* rgba, uint32_t count, std::string& why);

 private:
  friend bool decodeTextureImage(std::string_view, TextureImage&, std::string&);  // takes a whole image as it is
  struct State;
  std::unique_ptr<State> s_;
};

/// The pixel size `bytes` announces in its header, without decoding (for a
/// memory estimate); false when the header does not read.
bool textureImageSize(std::string_view bytes, uint32_t& width, uint32_t& height);

/// The memory TextureRowDecoder holds while it reads `bytes`, beyond the rows
/// it hands out, for a memory estimate (an upper bound; 0 when the header
/// does not read): a baseline JPEG is decoded row by row (libjpeg's row
/// buffers, under 32 rows of RGBA), a progressive JPEG keeps every
/// coefficient (2 bytes per sample), other formats are decoded whole (their
/// RGBA, and stb_image's own copy while it converts).
uint64_t textureDecoderBytes(std::string_view bytes);

/// The warning for image `name` whose data are damaged but decoded
/// (TextureImage::warning `why`): the one wording, whenever it is decoded.
std::string damagedImageWarning(const std::string& name, const std::string& why);

/// Throws vox::Error (BadInput, Setting::IgnoreMissingMaterials): image
/// `name` ("model.glb: image 3 'wood.jpg'") does not decode, for reason `why`
/// (decodeTextureImage's). The one message for it, whenever it is decoded.
[[noreturn]] void throwUndecodableImage(const std::string& name, const std::string& why);

}  // namespace vox
