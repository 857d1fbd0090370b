// Texture images of meshes (OBJ map_Kd files, glTF colour textures) decoded to
// 8-bit RGBA: the one decoder both mesh readers use.
//
// JPEG goes through libjpeg-turbo (Debian's libjpeg62-turbo): its SIMD
// decoder is 2-3x faster than stb_image's on the large JPEG textures
// photogrammetry and generated models carry, and decoding was most of the
// cost a textured bake adds. It decodes with the exact integer IDCT
// (JDCT_ISLOW) and integer upsampling, so the pixels are the same on every
// CPU. WebP (EXT_texture_webp) goes through libwebp; PNG and the other formats
// stb_image reads through stb_image.
//
// Thread-safe: each call decodes on the calling thread with its own state.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace vox {

struct TextureImage {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, row 0 = the image's top row
};

/// The largest image decoded, in pixels (a 16384 x 16384 texture: 1 GiB as RGBA);
/// a header announcing more is refused before any pixel memory is taken.
inline constexpr uint64_t kMaxTexturePixels = uint64_t(1) << 28;

/// Decodes `bytes` (the whole encoded file). On failure returns false and sets
/// `why` to a short reason ("not a PNG, JPEG or WebP", "a CMYK JPEG", "truncated
/// JPEG data", ...); `out` is then unspecified.
bool decodeTextureImage(std::string_view bytes, TextureImage& out, std::string& why);

/// The pixel size `bytes` announces in its header, without decoding (for a
/// memory estimate); false when the header does not read.
bool textureImageSize(std::string_view bytes, uint32_t& width, uint32_t& height);

/// Throws vox::Error (BadInput, Setting::IgnoreMissingMaterials): image
/// `name` ("model.glb: image 3 'wood.jpg'") does not decode, for reason `why`
/// (decodeTextureImage's). The one message for it, whenever it is decoded.
[[noreturn]] void throwUndecodableImage(const std::string& name, const std::string& why);

}  // namespace vox
