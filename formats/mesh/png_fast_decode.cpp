#include "formats/mesh/png_fast_decode.h"

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

constexpr uint8_t kMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// Ancillary chunks libpng reads without changing the pixels or text it gives
// vox's reader (no gamma, background or shift transform is asked for).
bool harmlessAncillary(const uint8_t* type) {
  static const char* const kNames[] = {"gAMA", "sRGB", "cHRM", "iCCP", "pHYs", "oFFs", "pCAL",
                                       "sCAL", "tIME", "bKGD", "sBIT", "eXIf"};
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

#ifdef __SSE2__
// The AVG and PAETH filters of 8-bit RGB and RGBA rows, a pixel at a time
// with its 3 or 4 bytes side by side in 16-bit lanes (each byte depends on
// the pixel to its left, so the bytes of one pixel are what can go
// together): the byte-serial loops were most of decoding a photographic
// PNG texture. Pixels are loaded and stored `bpp` bytes at a time, so the
// in-place layout below holds as for the scalar loops.
// A pixel's bytes in the low 16-bit lanes. kLoad 4 for an RGB pixel reads the
// byte after it too (its lane is never stored): one load instead of a 3-byte
// copy through the stack, whose store-to-load stall was most of the loop.
// The caller keeps that byte inside the buffer.
template <size_t kLoad>
inline __m128i loadPixel(const uint8_t* p) {
  uint32_t v = 0;
  std::memcpy(&v, p, kLoad);
  return _mm_unpacklo_epi8(_mm_cvtsi32_si128(int(v)), _mm_setzero_si128());
}
inline __m128i absDiff16(__m128i x, __m128i y) {
  const __m128i d = _mm_sub_epi16(x, y);
  return _mm_max_epi16(d, _mm_sub_epi16(_mm_setzero_si128(), d));
}
// PNG's Paeth predictor on 16-bit lanes: a (left), b (up) or c (up left),
// whichever is closest to a + b - c, ties to a, then b.
inline __m128i paeth16(__m128i a, __m128i b, __m128i c) {
  const __m128i pa = absDiff16(b, c), pb = absDiff16(a, c);
  const __m128i pc = absDiff16(_mm_add_epi16(a, b), _mm_add_epi16(c, c));
  const __m128i takeA = _mm_andnot_si128(_mm_or_si128(_mm_cmpgt_epi16(pa, pb), _mm_cmpgt_epi16(pa, pc)),
                                         _mm_set1_epi16(-1));
  const __m128i takeB = _mm_andnot_si128(_mm_or_si128(takeA, _mm_cmpgt_epi16(pb, pc)), _mm_set1_epi16(-1));
  const __m128i takeC = _mm_andnot_si128(_mm_or_si128(takeA, takeB), _mm_set1_epi16(-1));
  return _mm_or_si128(_mm_or_si128(_mm_and_si128(takeA, a), _mm_and_si128(takeB, b)), _mm_and_si128(takeC, c));
}
// out[i] = raw[i] + predict(left, up, up left) for the pixels after the first.
template <size_t kBpp, class Predict>
void pixelsAfterFirstOf(const uint8_t* raw, const uint8_t* prev, uint8_t* out, size_t n, Predict predict) {
  __m128i left = loadPixel<kBpp>(out), upLeft = loadPixel<kBpp>(prev);
  auto pixel = [&](size_t i, __m128i up, __m128i r) {
    const __m128i x = _mm_add_epi16(r, predict(left, up, upLeft));
    const __m128i bytes = _mm_packus_epi16(_mm_and_si128(x, _mm_set1_epi16(0xFF)), _mm_setzero_si128());
    const uint32_t v = uint32_t(_mm_cvtsi128_si32(bytes));
    std::memcpy(out + i, &v, kBpp);
    left = _mm_unpacklo_epi8(bytes, _mm_setzero_si128()), upLeft = up;
  };
  size_t i = kBpp;
  for (; i + 4 <= n; i += kBpp) pixel(i, loadPixel<4>(prev + i), loadPixel<4>(raw + i));  // byte i + 3 is in the row
  for (; i + kBpp <= n; i += kBpp) pixel(i, loadPixel<kBpp>(prev + i), loadPixel<kBpp>(raw + i));
}
template <class Predict>
void pixelsAfterFirst(const uint8_t* raw, const uint8_t* prev, uint8_t* out, size_t n, size_t bpp, Predict predict) {
  if (bpp == 3) pixelsAfterFirstOf<3>(raw, prev, out, n, predict);
  else pixelsAfterFirstOf<4>(raw, prev, out, n, predict);
}
#endif

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
#ifdef __SSE2__
      if (prev && (bpp == 3 || bpp == 4) && n >= bpp) {
        for (size_t i = 0; i < bpp; ++i) out[i] = uint8_t(raw[i] + (prev[i] >> 1));
        pixelsAfterFirst(raw, prev, out, n, bpp, [](__m128i a, __m128i b, __m128i) {
          return _mm_srli_epi16(_mm_add_epi16(a, b), 1);
        });
        return true;
      }
#endif
      for (size_t i = 0; i < n; ++i) {
        const unsigned left = i >= bpp ? out[i - bpp] : 0, up = prev ? prev[i] : 0;
        out[i] = uint8_t(raw[i] + ((left + up) >> 1));
      }
      return true;
    case 4:
#ifdef __SSE2__
      if (prev && (bpp == 3 || bpp == 4) && n >= bpp) {
        for (size_t i = 0; i < bpp; ++i) out[i] = uint8_t(raw[i] + prev[i]);  // paeth(0, up, 0) = up
        pixelsAfterFirst(raw, prev, out, n, bpp, paeth16);
        return true;
      }
#endif
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

std::string firstFailedPngCrc(const uint8_t* data, size_t size) {
  if (size < 8 || std::memcmp(data, kMagic, 8) != 0) return {};
  for (size_t at = 8; at + 12 <= size;) {
    const uint32_t length = be32(data + at);
    if (length > size - at - 12) break;  // cut short: the reader decides about that
    const uint8_t* type = data + at + 4;
    if (libdeflate_crc32(0, type, size_t(length) + 4) != be32(type + 4 + length))
      return "PNG: chunk '" + std::string(reinterpret_cast<const char*>(type), 4) + "' at byte " +
             std::to_string(at) + " fails its CRC";
    if (isType(type, "IEND")) break;
    at += size_t(length) + 12;
  }
  return {};
}

bool decodePngFast(const uint8_t* data, size_t size, DecodedPng& out, PngReader reader) {
  const bool stb = reader == PngReader::StbImage;
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
    } else if (stb && (type[0] & 0x20) && !isType(type, "tRNS")) {
      // an ancillary chunk stb_image skips
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
  // A window under 32 KB: libpng enforces it, libdeflate (like stb_image)
  // does not; such streams come from small images, which libpng reads
  // quickly enough.
  if (streamBytes < 2 || (!stb && (stream[0] >> 4) != 7)) return false;
  // Inflated straight into the image's pixels, then unfiltered in place:
  // no second image-sized buffer (fresh memory costs more than the copy).
  const size_t n = size_t(rowBytes), filtered = (n + 1) * height;
  DecodedPng image;
  image.width = width, image.height = height, image.channels = uint32_t(channels);
  image.bitDepth = uint32_t(depth);
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
