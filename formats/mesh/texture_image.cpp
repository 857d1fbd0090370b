#include "formats/mesh/texture_image.h"

#include <jpeglib.h>
#include <stb/stb_image.h>
#include <webp/decode.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <limits>

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
};

[[noreturn]] void jpegFail(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<JpegError*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

void jpegIgnoreWarning(j_common_ptr, int) {}

bool decodeJpeg(std::string_view bytes, TextureImage& out, std::string& why) {
  jpeg_decompress_struct cinfo{};
  JpegError err{};
  cinfo.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = jpegFail;
  err.mgr.emit_message = jpegIgnoreWarning;  // a corrupt-data warning still decodes, as stb_image does
  // Everything that must survive a longjmp lives outside this frame's registers.
  TextureImage* volatile target = &out;
  if (setjmp(err.jump)) {
    why = std::string("JPEG: ") + err.message;
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&cinfo, TRUE);
  if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
    why = "a CMYK JPEG (save it as RGB)";
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  if (tooLarge(cinfo.image_width, cinfo.image_height, why)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  cinfo.out_color_space = JCS_EXT_RGBA;  // libjpeg-turbo: RGBA written directly, alpha 255
  cinfo.dct_method = JDCT_ISLOW;         // exact integer IDCT: the same pixels on every CPU
  jpeg_start_decompress(&cinfo);
  target->width = cinfo.output_width;
  target->height = cinfo.output_height;
  target->rgba.resize(size_t(cinfo.output_width) * cinfo.output_height * 4);
  const size_t stride = size_t(cinfo.output_width) * 4;
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = target->rgba.data() + stride * cinfo.output_scanline;
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  return true;
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

bool decodeStb(std::string_view bytes, TextureImage& out, std::string& why) {
  if (bytes.size() > size_t(std::numeric_limits<int>::max())) {
    why = "the file is larger than 2 GiB";
    return false;
  }
  int w = 0, h = 0, n = 0;
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  if (stbi_info_from_memory(data, int(bytes.size()), &w, &h, &n) && tooLarge(uint64_t(w), uint64_t(h), why)) return false;
  stbi_uc* px = stbi_load_from_memory(data, int(bytes.size()), &w, &h, &n, 4);
  if (!px) {
    why = std::string("not a PNG, JPEG or WebP that decodes (") + stbi_failure_reason() + ")";
    return false;
  }
  out.width = uint32_t(w);
  out.height = uint32_t(h);
  out.rgba.assign(px, px + size_t(w) * size_t(h) * 4);
  stbi_image_free(px);
  return true;
}

}  // namespace

bool decodeTextureImage(std::string_view bytes, TextureImage& out, std::string& why) {
  out = TextureImage{};
  if (bytes.empty()) {
    why = "the image is empty";
    return false;
  }
  if (isJpeg(bytes)) return decodeJpeg(bytes, out, why);
  if (isWebp(bytes)) return decodeWebp(bytes, out, why);
  return decodeStb(bytes, out, why);
}

namespace {

bool jpegSize(std::string_view bytes, uint32_t& width, uint32_t& height) {
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
  jpeg_destroy_decompress(&cinfo);
  return true;
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

void throwUndecodableImage(const std::string& name, const std::string& why) {
  throwBadInput(name + " cannot be decoded (" + why + "); re-export it, or leave its textures out",
                Setting::IgnoreMissingMaterials);
}

}  // namespace vox
