#include "formats/mesh/texture_image.h"

#include <jpeglib.h>
// after jpeglib.h, which it needs
#include <jerror.h>
#include <stb/stb_image.h>
#include <webp/decode.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <limits>

#include "formats/mesh/png_fast_decode.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

bool isJpeg(std::string_view b) { return b.size() >= 3 && uint8_t(b[0]) == 0xFF && uint8_t(b[1]) == 0xD8 && uint8_t(b[2]) == 0xFF; }
bool isWebp(std::string_view b) { return b.size() >= 12 && b.substr(0, 4) == "RIFF" && b.substr(8, 4) == "WEBP"; }

bool tooLarge(uint64_t w, uint64_t h, std::string& why) {
  if (w == 0 || h == 0) {
    why = "the image has no pixels";
    return true;
  }
  if (w * h > kMaxTexturePixels) {
    why = std::to_string(w) + " x " + std::to_string(h) + " pixels, above the 2^28 pixels a texture may have";
    return true;
  }
  return false;
}

// libjpeg reports errors through a callback that must not return: jump back
// to decodeJpeg with the message.
struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
  char warning[JMSG_LENGTH_MAX];  // the first corrupt-data warning ("" while none)
};

[[noreturn]] void jpegFail(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<JpegError*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

void jpegIgnoreWarning(j_common_ptr, int) {}

/// libjpeg's warnings (level -1: corrupt data it decodes past, as stb_image
/// and image viewers do) are kept, the first one worded; trace messages are
/// dropped, and so are the two warnings that leave the pixels alone (an
/// unknown JFIF revision, a bad ICC profile, which vox never applies).
void jpegKeepWarning(j_common_ptr cinfo, int level) {
  if (level >= 0) return;
  const int code = cinfo->err->msg_code;
  if (code == JWRN_JFIF_MAJOR || code == JWRN_BOGUS_ICC) return;
  auto* err = reinterpret_cast<JpegError*>(cinfo->err);
  if (cinfo->err->num_warnings++ == 0) (*cinfo->err->format_message)(cinfo, err->warning);
}

/// Reads `count` rows of `cinfo` into `rgba` (`stride` bytes each), counting
/// them in `next`; libjpeg's errors longjmp out of it.
void readJpegRows(jpeg_decompress_struct& cinfo, uint8_t* rgba, size_t stride, uint32_t count, uint32_t& next) {
  while (count > 0) {
    JSAMPROW rows[16];
    const uint32_t n = std::min<uint32_t>(count, 16);
    for (uint32_t i = 0; i < n; ++i) rows[i] = rgba + stride * i;
    const JDIMENSION got = jpeg_read_scanlines(&cinfo, rows, n);
    if (got == 0) ERREXIT(&cinfo, JERR_INPUT_EMPTY);  // cannot happen with an in-memory source: it pads with EOI
    rgba += stride * got, count -= got, next += got;
  }
}

bool decodeWebp(std::string_view bytes, TextureImage& out, std::string& why) {
  int w = 0, h = 0;
  if (!WebPGetInfo(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), &w, &h)) {
    why = "WebP: not a valid WebP header";
    return false;
  }
  if (tooLarge(uint64_t(w), uint64_t(h), why)) return false;
  out.width = uint32_t(w);
  out.height = uint32_t(h);
  out.rgba.resize(size_t(w) * size_t(h) * 4);
  if (!WebPDecodeRGBAInto(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), out.rgba.data(),
                          out.rgba.size(), w * 4)) {
    why = "WebP: the data does not decode";
    return false;
  }
  return true;
}

/// `png` as RGBA8 the way stb_image gives it: gray as (g, g, g), no alpha as
/// 255, 16-bit samples by their high byte.
void rgbaLikeStb(const DecodedPng& png, TextureImage& out) {
  out.width = png.width, out.height = png.height;
  const size_t pixels = size_t(png.width) * png.height, c = png.channels;
  out.rgba.resize(pixels * 4);
  uint8_t* o = out.rgba.data();
  if (png.bitDepth == 8 && c == 4) {
    std::memcpy(o, png.pixels.data(), pixels * 4);
    return;
  }
  if (png.bitDepth == 8 && c == 3) {  // the common RGB texture: a tight loop
    const uint8_t* in = png.pixels.data();
    for (size_t p = 0; p < pixels; ++p, o += 4, in += 3) o[0] = in[0], o[1] = in[1], o[2] = in[2], o[3] = 255;
    return;
  }
  auto sample = [&](size_t i) -> uint8_t {
    if (png.bitDepth == 8) return png.pixels[i];
    uint16_t v;
    std::memcpy(&v, png.pixels.data() + 2 * i, 2);
    return uint8_t(v >> 8);
  };
  for (size_t p = 0; p < pixels; ++p, o += 4) {
    const size_t at = p * c;
    if (c <= 2) o[0] = o[1] = o[2] = sample(at);
    else o[0] = sample(at), o[1] = sample(at + 1), o[2] = sample(at + 2);
    o[3] = c == 2 ? sample(at + 1) : c == 4 ? sample(at + 3) : 255;
  }
}

bool decodeStb(std::string_view bytes, TextureImage& out, std::string& why) {
  if (bytes.size() > size_t(std::numeric_limits<int>::max())) {
    why = "the file is larger than 2 GiB";
    return false;
  }
  int w = 0, h = 0, n = 0;
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  if (stbi_info_from_memory(data, int(bytes.size()), &w, &h, &n) && tooLarge(uint64_t(w), uint64_t(h), why)) return false;
  // PNGs of the common shapes through the libdeflate fast path: stb_image's
  // own inflate and filters took 1.5-3x as long on 2048^2 RGB textures
  // (docs/gltf.md, "PNG textures").
  if (DecodedPng png; decodePngFast(data, bytes.size(), png, PngReader::StbImage)) {
    rgbaLikeStb(png, out);
    return true;
  }
  stbi_uc* px = stbi_load_from_memory(data, int(bytes.size()), &w, &h, &n, 4);
  if (!px) {
    why = std::string("not a PNG, JPEG or WebP that decodes (") + stbi_failure_reason() + ")";
    return false;
  }
  out.width = uint32_t(w);
  out.height = uint32_t(h);
  out.rgba.assign(px, px + size_t(w) * size_t(h) * 4);
  stbi_image_free(px);
  // stb_image checks no CRC; the fast path declines a file whose CRC fails,
  // so only here can a damaged PNG decode.
  out.warning = firstFailedPngCrc(data, bytes.size());
  return true;
}

}  // namespace

struct TextureRowDecoder::State {
  bool jpeg = false;
  // JPEG: libjpeg's state, alive from open() to the destructor.
  jpeg_decompress_struct cinfo{};
  JpegError err{};
  bool created = false;
  // Other formats: the whole image, decoded by open().
  TextureImage whole;
  uint32_t width = 0, height = 0, next = 0;
  std::string warning;  // TextureImage::warning
  ~State() {
    if (created) jpeg_destroy_decompress(&cinfo);
  }
};

TextureRowDecoder::TextureRowDecoder() : s_(std::make_unique<State>()) {}
TextureRowDecoder::~TextureRowDecoder() = default;
uint32_t TextureRowDecoder::width() const { return s_->width; }
uint32_t TextureRowDecoder::height() const { return s_->height; }
uint32_t TextureRowDecoder::rowsRead() const { return s_->next; }
const std::string& TextureRowDecoder::warning() const { return s_->warning; }

bool TextureRowDecoder::open(std::string_view bytes, std::string& why) {
  State& s = *s_;
  if (bytes.empty()) {
    why = "the image is empty";
    return false;
  }
  if (!isJpeg(bytes)) {
    if (!(isWebp(bytes) ? decodeWebp(bytes, s.whole, why) : decodeStb(bytes, s.whole, why))) return false;
    s.width = s.whole.width, s.height = s.whole.height;
    s.warning = s.whole.warning;
    return true;
  }
  s.jpeg = true;
  s.cinfo.err = jpeg_std_error(&s.err.mgr);
  s.err.mgr.error_exit = jpegFail;
  s.err.mgr.emit_message = jpegKeepWarning;  // corrupt data still decode, as stb_image does, with a warning
  // Only State (on the heap) is touched between here and a longjmp back.
  if (setjmp(s.err.jump)) {
    why = std::string("JPEG: ") + s.err.message;
    return false;
  }
  jpeg_create_decompress(&s.cinfo);
  s.created = true;
  jpeg_mem_src(&s.cinfo, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&s.cinfo, TRUE);
  if (s.cinfo.jpeg_color_space == JCS_CMYK || s.cinfo.jpeg_color_space == JCS_YCCK) {
    why = "a CMYK JPEG (save it as RGB)";
    return false;
  }
  if (tooLarge(s.cinfo.image_width, s.cinfo.image_height, why)) return false;
  s.cinfo.out_color_space = JCS_EXT_RGBA;  // libjpeg-turbo: RGBA written directly, alpha 255
  s.cinfo.dct_method = JDCT_ISLOW;         // exact integer IDCT: the same pixels on every CPU
  jpeg_start_decompress(&s.cinfo);
  s.width = s.cinfo.output_width, s.height = s.cinfo.output_height;
  if (s.err.warning[0] && s.warning.empty()) s.warning = std::string("JPEG: ") + s.err.warning;
  return true;
}

bool TextureRowDecoder::read(uint8_t* rgba, uint32_t count, std::string& why) {
  State& s = *s_;
  count = std::min(count, s.height - s.next);
  if (count == 0) return true;  // the end was read (and finished) already
  const size_t stride = size_t(s.width) * 4;
  if (!s.jpeg) {
    std::memcpy(rgba, s.whole.rgba.data() + stride * s.next, stride * count);
    if ((s.next += count) == s.height) s.whole = TextureImage{};
    return true;
  }
  if (setjmp(s.err.jump)) {
    why = std::string("JPEG: ") + s.err.message;
    return false;
  }
  readJpegRows(s.cinfo, rgba, stride, count, s.next);
  if (s.next == s.height) jpeg_finish_decompress(&s.cinfo);
  if (s.err.warning[0] && s.warning.empty()) s.warning = std::string("JPEG: ") + s.err.warning;
  return true;
}

bool decodeTextureImage(std::string_view bytes, TextureImage& out, std::string& why) {
  out = TextureImage{};
  TextureRowDecoder decoder;
  if (!decoder.open(bytes, why)) return false;
  if (!decoder.s_->jpeg) {  // decoded whole already
    out = std::move(decoder.s_->whole);
    return true;
  }
  out.width = decoder.width();
  out.height = decoder.height();
  out.rgba.resize(size_t(out.width) * out.height * 4);
  if (!decoder.read(out.rgba.data(), out.height, why)) return false;
  out.warning = decoder.warning();
  return true;
}

std::string damagedImageWarning(const std::string& name, const std::string& why) {
  return name + ": damaged image data, decoded as far as they go (" + why +
         "); its colours may be wrong: re-export the image";
}

namespace {

/// The header of a JPEG: its size and whether it is progressive.
bool jpegHeader(std::string_view bytes, uint32_t& width, uint32_t& height, bool& progressive, int& components) {
  jpeg_decompress_struct cinfo{};
  JpegError err{};
  cinfo.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = jpegFail;
  err.mgr.emit_message = jpegIgnoreWarning;
  if (setjmp(err.jump)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&cinfo, TRUE);
  width = cinfo.image_width, height = cinfo.image_height;
  progressive = cinfo.progressive_mode;
  components = cinfo.num_components;
  jpeg_destroy_decompress(&cinfo);
  return true;
}

bool jpegSize(std::string_view bytes, uint32_t& width, uint32_t& height) {
  bool progressive = false;
  int components = 0;
  return jpegHeader(bytes, width, height, progressive, components);
}

}  // namespace

bool textureImageSize(std::string_view bytes, uint32_t& width, uint32_t& height) {
  width = height = 0;
  int w = 0, h = 0, n = 0;
  if (isJpeg(bytes)) return jpegSize(bytes, width, height);
  if (isWebp(bytes)) {
    if (!WebPGetInfo(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), &w, &h)) return false;
  } else if (bytes.size() > size_t(std::numeric_limits<int>::max()) ||
             !stbi_info_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &w, &h, &n)) {
    return false;
  }
  width = uint32_t(std::max(w, 0)), height = uint32_t(std::max(h, 0));
  return true;
}

uint64_t textureDecoderBytes(std::string_view bytes) {
  uint32_t w = 0, h = 0;
  if (isJpeg(bytes)) {
    bool progressive = false;
    int components = 0;
    if (!jpegHeader(bytes, w, h, progressive, components)) return 0;
    return progressive ? uint64_t(w) * h * uint64_t(std::max(components, 1)) * 2 : uint64_t(w) * 4 * 32;
  }
  if (!textureImageSize(bytes, w, h)) return 0;
  return uint64_t(w) * h * 4 * 2;
}

void throwUndecodableImage(const std::string& name, const std::string& why) {
  throwBadInput(name + " cannot be decoded (" + why + "); re-export it, or leave its textures out",
                Setting::IgnoreMissingMaterials);
}

}  // namespace vox
