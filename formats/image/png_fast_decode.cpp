#include "formats/image/png_fast_decode.h"

#include <libdeflate.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include <bit>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace vox {

namespace {

uint32_t be32(const uint8_t* p) { return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3]; }

bool isType(const uint8_t* type, const char* name) { return std::memcmp(type, name, 4) == 0; }

// Ancillary chunks libpng reads without changing the pixels or text it gives
// vox's reader (no gamma, background or shift transform is asked for).
bool harmlessAncillary(const uint8_t* type) {
  static const char* const kNames[] = {"gAMA", "sRGB", "pHYs", "tIME", "cHRM", "bKGD", "sBIT"};
  for (const char* n : kNames)
    if (isType(type, n)) return true;
  return false;
}

// libpng's defaults, which vox does not change: larger images are refused,
// and a text chunk over the ancillary allocation limit is skipped.
constexpr uint32_t kLibpngMaxDimension = 1000000;
constexpr uint32_t kMaxTextChunk = 1 << 20;  // well under libpng's 8 MB limit
constexpr size_t kMaxTextChunks = 256;       // well under libpng's cache of 1000

uint8_t paeth(uint8_t a, uint8_t b, uint8_t c) {
  const int p = int(a) + int(b) - int(c);
  const int pa = std::abs(p - int(a)), pb = std::abs(p - int(b)), pc = std::abs(p - int(c));
  return (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c);
}

// One scanline: `raw` (filtered, without its filter byte) into `out`, given
// the row above (`prev`, null for the first row). `bpp`: bytes per pixel.
// `out` may start before `raw` in the same buffer (rows are unfiltered in
// place, each moved down over the filter bytes before it): every byte is
// read before an earlier byte of the output can reach it.
bool unfilterRow(uint8_t filter, const uint8_t* raw, const uint8_t* prev, uint8_t* out, size_t n, size_t bpp) {
  switch (filter) {
    case 0: std::memmove(out, raw, n); return true;
    case 1:
      for (size_t i = 0; i < bpp && i < n; ++i) out[i] = raw[i];
      if (bpp == 4) {  // RGBA8, the common case: running sums of 4-byte pixels
        size_t i = 4;
#ifdef __SSE2__
        // Four pixels at a time: prefix sums within the 16 bytes, plus the
        // pixel before them. `out` is written only after its 16 bytes of
        // `raw` are read, and never past them (see above).
        __m128i left = _mm_cvtsi32_si128(0);
        std::memcpy(&left, out, 4);
        left = _mm_shuffle_epi32(left, 0);
        for (; i + 16 <= n; i += 16) {
          __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(raw + i));
          x = _mm_add_epi8(x, _mm_slli_si128(x, 4));
          x = _mm_add_epi8(x, _mm_slli_si128(x, 8));
          x = _mm_add_epi8(x, left);
          _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), x);
          left = _mm_shuffle_epi32(x, 0xFF);
        }
#endif
        for (; i < n; ++i) out[i] = uint8_t(raw[i] + out[i - 4]);
      } else {
        for (size_t i = bpp; i < n; ++i) out[i] = uint8_t(raw[i] + out[i - bpp]);
      }
      return true;
    case 2:
      if (!prev) std::memmove(out, raw, n);
      else
        for (size_t i = 0; i < n; ++i) out[i] = uint8_t(raw[i] + prev[i]);
      return true;
    case 3:
      for (size_t i = 0; i < n; ++i) {
        const unsigned left = i >= bpp ? out[i - bpp] : 0, up = prev ? prev[i] : 0;
        out[i] = uint8_t(raw[i] + ((left + up) >> 1));
      }
      return true;
    case 4:
      for (size_t i = 0; i < n; ++i) {
        const uint8_t left = i >= bpp ? out[i - bpp] : 0, up = prev ? prev[i] : 0;
        const uint8_t upLeft = (prev && i >= bpp) ? prev[i - bpp] : 0;
        out[i] = uint8_t(raw[i] + paeth(left, up, upLeft));
      }
      return true;
    default: return false;  // libpng: "bad adaptive filter value"
  }
}

struct Decompressor {
  libdeflate_decompressor* d = libdeflate_alloc_decompressor();
  ~Decompressor() {
    if (d) libdeflate_free_decompressor(d);
  }
};

}  // namespace

bool decodePngFast(const uint8_t* data, size_t size, Image& out) {
  static const uint8_t kMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size < 8 + 25 || std::memcmp(data, kMagic, 8) != 0) return false;

  uint32_t width = 0, height = 0;
  int depth = 0, colorType = -1;
  std::vector<std::pair<const uint8_t*, size_t>> idat;
  bool idatDone = false, ended = false;
  std::vector<std::pair<std::string, std::string>> text;
  size_t at = 8;
  for (bool first = true; at + 12 <= size; first = false) {
    const uint32_t length = be32(data + at);
    const uint8_t* type = data + at + 4;
    if (length > 0x7fffffffu || length > size - at - 12) return false;  // PNG lengths are 31-bit
    const uint8_t* body = data + at + 8;
#ifndef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION  // the fuzzer's mutations would rarely get past the CRCs
    if (libdeflate_crc32(0, type, size_t(length) + 4) != be32(body + length)) return false;
#endif
    if (first != isType(type, "IHDR")) return false;
    if (isType(type, "IHDR")) {
      if (length != 13) return false;
      width = be32(body), height = be32(body + 4);
      depth = body[8], colorType = body[9];
      if (width == 0 || height == 0 || width > kLibpngMaxDimension || height > kLibpngMaxDimension) return false;
      if (depth != 8 && depth != 16) return false;
      if (colorType != 0 && colorType != 2 && colorType != 4 && colorType != 6) return false;
      if (body[10] != 0 || body[11] != 0 || body[12] != 0) return false;  // compression, filter method, interlace
    } else if (isType(type, "IDAT")) {
      if (idatDone) return false;
      idat.emplace_back(body, length);
    } else if (isType(type, "IEND")) {
      ended = true;
      break;
    } else if (isType(type, "tEXt")) {
      if (length > kMaxTextChunk || text.size() >= kMaxTextChunks) return false;
      const void* nul = std::memchr(body, 0, length);
      if (!nul) return false;
      const size_t keyLength = size_t(static_cast<const uint8_t*>(nul) - body);
      if (keyLength == 0 || keyLength > 79) return false;
      text.emplace_back(std::string(reinterpret_cast<const char*>(body), keyLength),
                        std::string(reinterpret_cast<const char*>(body) + keyLength + 1, length - keyLength - 1));
    } else if (!harmlessAncillary(type)) {
      return false;  // PLTE, tRNS, zTXt, iTXt, unknown chunks: libpng's business
    }
    if (!idat.empty() && !isType(type, "IDAT")) idatDone = true;
    at += size_t(length) + 12;
  }
  if (!ended || idat.empty()) return false;

  const size_t channels = colorType == 0 ? 1 : colorType == 4 ? 2 : colorType == 2 ? 3 : 4;
  const size_t sample = depth / 8, bpp = channels * sample;
  const uint64_t rowBytes = uint64_t(width) * bpp;
  // image_png.cpp's plausibility bound (deflate's 1032:1, libpng's 32:1 expansion).
  if (rowBytes * height > (uint64_t(size) + 1) * 1032 * 32) return false;

  // The zlib stream: one IDAT's bytes where it can, else the IDATs joined.
  std::vector<uint8_t> joined;
  const uint8_t* stream = idat[0].first;
  size_t streamBytes = idat[0].second;
  if (idat.size() > 1) {
    for (const auto& [p, n] : idat) joined.insert(joined.end(), p, p + n);
    stream = joined.data(), streamBytes = joined.size();
  }
  // A window under 32 KB: libpng enforces it, libdeflate does not; such
  // streams come from small images, which libpng reads quickly enough.
  if (streamBytes < 2 || (stream[0] >> 4) != 7) return false;
  // Inflated straight into the image's pixels, then unfiltered in place:
  // no second image-sized buffer (fresh memory costs more than the copy).
  const size_t n = size_t(rowBytes), filtered = (n + 1) * height;
  Image image;
  image.width = width, image.height = height, image.channels = uint32_t(channels);
  image.type = depth == 16 ? SampleType::U16 : SampleType::U8;
  image.pixels.resize(filtered);
  Decompressor inflater;
  if (!inflater.d) return false;
  size_t usedIn = 0, produced = 0;
  if (libdeflate_zlib_decompress_ex(inflater.d, stream, streamBytes, image.pixels.data(), filtered, &usedIn,
                                    &produced) != LIBDEFLATE_SUCCESS ||
      produced != filtered || usedIn != streamBytes)
    return false;
  uint8_t* const px = image.pixels.data();
  for (uint32_t y = 0; y < height; ++y) {
    const uint8_t* in = px + size_t(y) * (n + 1);
    uint8_t* row = px + size_t(y) * n;
    if (!unfilterRow(in[0], in + 1, y ? row - n : nullptr, row, n, bpp)) return false;
  }
  image.pixels.resize(n * height);  // shrinks in place
  if (depth == 16 && std::endian::native == std::endian::little)  // PNG is big-endian; samples are native
    for (size_t i = 0; i + 1 < image.pixels.size(); i += 2) std::swap(image.pixels[i], image.pixels[i + 1]);
  image.text = std::move(text);
  out = std::move(image);
  return true;
}

}  // namespace vox
