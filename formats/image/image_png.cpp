#include <png.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>

#include "formats/core/file_util.h"
#include "formats/image/image.h"
#include "formats/mesh/png_fast_decode.h"
#include "libvox/core/error.h"

namespace vox {

const char* sampleTypeName(SampleType t) {
  switch (t) {
    case SampleType::U8: return "uint8";
    case SampleType::U16: return "uint16";
    case SampleType::U32: return "uint32";
    case SampleType::F16: return "half";
    case SampleType::F32: return "float";
  }
  return "?";
}

size_t sampleBytes(SampleType t) {
  switch (t) {
    case SampleType::U8: return 1;
    case SampleType::U16:
    case SampleType::F16: return 2;
    case SampleType::U32:
    case SampleType::F32: return 4;
  }
  return 0;
}

std::string Image::textValue(const std::string& key) const {
  for (const auto& [k, v] : text)
    if (k == key) return v;
  return {};
}

namespace {

using FilePtr = std::unique_ptr<FILE, int (*)(FILE*)>;

bool hasMagic(const std::string& path, const uint8_t* magic, size_t n) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;  // never block on a FIFO
  FilePtr f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return false;
  uint8_t buf[8] = {};
  return std::fread(buf, 1, n, f.get()) == n && std::memcmp(buf, magic, n) == 0;
}

[[noreturn]] void pngError(png_structp png, png_const_charp message) {
  // libpng requires this not to return; we unwind with an exception carrying the text.
  auto* what = static_cast<std::string*>(png_get_error_ptr(png));
  *what = message;
  png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}

}  // namespace

bool isPngFile(const std::string& path) {
  static const uint8_t magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return hasMagic(path, magic, 8);
}

bool isExrFile(const std::string& path) {
  static const uint8_t magic[4] = {0x76, 0x2f, 0x31, 0x01};
  return hasMagic(path, magic, 4);
}

namespace {

// libpng reports errors by longjmp. These helpers hold the setjmp and touch no
// C++ object with a destructor, so nothing is skipped when libpng jumps out.
bool pngWriteAll(png_structp png, png_infop info, FILE* f, int level, uint32_t w, uint32_t h, int depth,
                 int colorType, png_text* texts, int textCount, const std::function<const uint8_t*(uint32_t)>& rowAt,
                 bool swap16) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_set_compression_level(png, level);
  // Atlases are mostly runs of zero texels: the SUB filter alone compresses them as
  // well as adaptive filtering (measured on the demo atlases) at a fraction of the time.
  png_set_filter(png, 0, PNG_FILTER_SUB);
  png_set_IHDR(png, info, w, h, depth, colorType, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  if (textCount > 0) png_set_text(png, info, texts, textCount);
  png_write_info(png, info);
  if (swap16) png_set_swap(png);  // PNG is big-endian; our samples are native
  // Row by row (what png_write_image does for a non-interlaced image), so a
  // caller can produce rows on demand instead of holding the image.
  for (uint32_t y = 0; y < h; ++y) png_write_row(png, const_cast<png_bytep>(rowAt(y)));
  png_write_end(png, nullptr);
  return true;
}

bool pngReadHeader(png_structp png, png_infop info, FILE* f, uint32_t* w, uint32_t* h, uint32_t* channels,
                   int* depth) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_read_info(png, info);
  const int colorType = png_get_color_type(png, info);
  const int inDepth = png_get_bit_depth(png, info);
  if (colorType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colorType == PNG_COLOR_TYPE_GRAY && inDepth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (inDepth == 16) png_set_swap(png);
  png_read_update_info(png, info);
  *w = png_get_image_width(png, info);
  *h = png_get_image_height(png, info);
  *channels = png_get_channels(png, info);
  *depth = png_get_bit_depth(png, info);
  return true;
}

/// The first chunk whose length runs past the end of the input, as a message
/// ("" when every chunk up to IEND fits). libpng allocates a text chunk whole
/// at the length its header claims before reading it: a 797-byte file whose
/// tEXt chunk claims 1.9 GB took 1.9 GB and 3.8 s before "Read Error".
/// `readAt(offset, 8 bytes)` reads a chunk's length and type.
template <class ReadAt>
std::string chunkPastEnd(uint64_t total, ReadAt readAt) {
  uint64_t at = 8;  // after the signature
  uint8_t h[8];
  while (at + 12 <= total && readAt(at, h)) {
    const uint64_t length = (uint64_t(h[0]) << 24) | (uint64_t(h[1]) << 16) | (uint64_t(h[2]) << 8) | h[3];
    std::string type;
    for (int i = 4; i < 8; ++i) type += std::isalpha(h[i]) ? char(h[i]) : '?';
    if (length > total - at - 12)
      return "chunk '" + type + "' at byte " + std::to_string(at) + " claims " + std::to_string(length) +
             " bytes, more than the " + std::to_string(total - at - 12) + " left in the file";
    if (type == "IEND") break;
    at += 12 + length;
  }
  return {};
}

/// A header whose pixels its input could not hold compressed is refused
/// before they are allocated (a 100-byte file claiming 30000 x 30000 would
/// otherwise take 3.6 GB, and 10^6 x 10^6 end as "out of memory"). deflate
/// expands at most 1032:1, and libpng's expansions to 8-bit RGBA at most 32:1
/// (1-bit palette), so `inputBytes` * 1032 * 32 bounds every real PNG.
/// Returns the message, or "" for a plausible size.
std::string implausibleSize(const Image& image, uint64_t inputBytes, const std::string& name) {
  const uint64_t decoded = uint64_t(image.rowBytes()) * image.height;
  const uint64_t bound = (inputBytes + 1) * 1032 * 32;
  if (decoded <= bound) return {};
  return name + ": corrupt or truncated PNG: its header says " + std::to_string(image.width) + " x " +
                  std::to_string(image.height) + " pixels (" + std::to_string(decoded) +
                  " bytes), more than its " + std::to_string(inputBytes) + " bytes can hold compressed";
}

bool pngReadRows(png_structp png, png_infop info, png_bytep* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);
  return true;
}

}  // namespace

void requirePngSides(uint32_t width, uint32_t height, const std::string& path) {
  for (const auto& [side, pixels] : {std::pair<const char*, uint32_t>{"wide", width}, {"high", height}})
    if (pixels > kMaxPngSide)
      throwUsage(outputName(path) + ": cannot write a PNG " + std::to_string(pixels) + " pixels " + side + ": past " +
                 std::to_string(kMaxPngSide) + ", the largest PNG side libpng (and so vox) reads back; write an image " +
                 "at most " + std::to_string(kMaxPngSide) + " pixels " + side);
}

void writePng(const Image& image, const std::string& path, int zlibLevel) {
  writePngRows(image.width, image.height, image.channels, image.type, image.text, path, zlibLevel,
               [&image](uint32_t y) { return image.pixels.data() + y * image.rowBytes(); });
}

void writePngRows(uint32_t width, uint32_t height, uint32_t channels, SampleType type,
                  const std::vector<std::pair<std::string, std::string>>& text, const std::string& path, int zlibLevel,
                  const std::function<const uint8_t*(uint32_t y)>& row) {
  requirePngSides(width, height, path);
  if (type != SampleType::U8 && type != SampleType::U16)
    throw Error(ErrorKind::Internal, path + ": PNG holds 8- or 16-bit samples, not " + sampleTypeName(type));
  if (channels < 1 || channels > 4 || width == 0 || height == 0)
    throw Error(ErrorKind::Internal, path + ": bad image shape for PNG");
  FilePtr f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f) throwIo(path + ": cannot create the file: " + std::strerror(errno));
  std::string message;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &message, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) throwIo(path + ": libpng could not start");
  const int colorTypes[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                             PNG_COLOR_TYPE_RGBA};
  std::vector<png_text> texts(text.size());
  for (size_t i = 0; i < texts.size(); ++i) {
    texts[i].compression = PNG_TEXT_COMPRESSION_NONE;
    texts[i].key = const_cast<png_charp>(text[i].first.c_str());
    texts[i].text = const_cast<png_charp>(text[i].second.c_str());
    texts[i].text_length = text[i].second.size();
  }
  const bool ok = pngWriteAll(png, info, f.get(), zlibLevel, width, height, type == SampleType::U16 ? 16 : 8,
                              colorTypes[channels], texts.data(), int(texts.size()), row, type == SampleType::U16);
  png_destroy_write_struct(&png, &info);
  if (!ok) throwIo(path + ": PNG write failed: " + message);
  if (std::fflush(f.get()) != 0 || std::ferror(f.get())) throwIo(outputName(path) + ": cannot write the file: " + std::strerror(errno));
}

/// The fast path's decoding as an Image (the same pixels libpng's gives).
Image imageOf(DecodedPng&& d) {
  Image image;
  image.width = d.width, image.height = d.height, image.channels = d.channels;
  image.type = d.bitDepth == 16 ? SampleType::U16 : SampleType::U8;
  image.pixels = std::move(d.pixels);
  image.text = std::move(d.text);
  return image;
}

/// The pixels and text chunks of the PNG that `f` reads (from its start),
/// `bytes` long; destroys png/info. Shared by the file and memory readers.
static Image decodePng(png_structp png, png_infop info, FILE* f, uint64_t bytes, const std::string& name,
                       const std::string& message) {
  Image image;
  int depth = 8;
  bool ok = pngReadHeader(png, info, f, &image.width, &image.height, &image.channels, &depth);
  if (ok) {
    image.type = depth == 16 ? SampleType::U16 : SampleType::U8;
    if (const std::string why = implausibleSize(image, bytes, name); !why.empty()) {
      png_destroy_read_struct(&png, &info, nullptr);
      throwBadInput(why);
    }
    image.pixels.assign(image.rowBytes() * image.height, 0);
    std::vector<png_bytep> rows(image.height);
    for (uint32_t y = 0; y < image.height; ++y) rows[y] = image.pixels.data() + y * image.rowBytes();
    ok = pngReadRows(png, info, rows.data());
  }
  if (ok) {
    png_textp texts = nullptr;
    int count = 0;
    png_get_text(png, info, &texts, &count);
    for (int i = 0; i < count; ++i)
      image.text.emplace_back(texts[i].key, std::string(texts[i].text, texts[i].text_length));
  }
  png_destroy_read_struct(&png, &info, nullptr);
  if (!ok) throwBadInput(name + ": corrupt or truncated PNG: " + message);
  return image;
}

/// A PNG in memory, `name` in messages (`kind`: "file" or "image"): the fast
/// path where it takes the file (formats/mesh/png_fast_decode.h), else
/// libpng, which also words every error.
static Image readPngBytes(const uint8_t* data, size_t size, const std::string& name, const char* kind) {
  static const uint8_t magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size < 8 || std::memcmp(data, magic, 8) != 0)
    throwBadInput(name + ": not a PNG " + kind + " (wrong signature)");
  const std::string pastEnd = chunkPastEnd(size, [&](uint64_t at, uint8_t* h) {
    std::memcpy(h, data + at, 8);
    return true;
  });
  if (!pastEnd.empty()) throwBadInput(name + ": corrupt or truncated PNG: " + pastEnd);
  if (DecodedPng fast; decodePngFast(data, size, fast)) return imageOf(std::move(fast));
  // fmemopen gives libpng the FILE* its reader expects, over the same bytes.
  FilePtr f(fmemopen(const_cast<uint8_t*>(data), size, "rb"), &std::fclose);
  if (!f) throwIo(name + ": cannot read the PNG bytes from memory");
  std::string message;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &message, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) throwIo(name + ": libpng could not start");
  return decodePng(png, info, f.get(), size, name, message);
}

Image readPng(const std::string& path) {
  const FileView bytes(path);  // names the file if it is not a regular, readable one
  return readPngBytes(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path, "file");
}

}  // namespace vox

// ---------------------------------------------------------------- from memory
// (declared in formats/image/png_memory.h)

namespace vox {

Image readPngMemory(const uint8_t* data, size_t size, const std::string& name) {
  return readPngBytes(data, size, name, "image");
}

}  // namespace vox
