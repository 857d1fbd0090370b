// Images as vox writes and reads them: atlases, bitmaps, renders.
//
// PNG through libpng and EXR through OpenEXR directly, not OpenImageIO: Debian's
// OpenImageIO costs ~350 ms at every process start (docs/startup.md), and
// these two libraries cover every format the tool writes.
//
// Conventions: row 0 is the top of the image; channels are interleaved;
// samples are native-endian in `pixels`; text entries become PNG tEXt chunks or
// EXR string attributes, in the order given (so files are byte-identical for
// identical inputs: no timestamps are written).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace vox {

enum class SampleType { U8, U16, U32, F16, F32 };

const char* sampleTypeName(SampleType t);  // "uint8", "uint16", "uint32", "half", "float"
size_t sampleBytes(SampleType t);

struct Image {
  uint32_t width = 0, height = 0;
  uint32_t channels = 4;  // 1 (gray / R), 2, 3 (RGB) or 4 (RGBA)
  SampleType type = SampleType::U8;
  std::vector<uint8_t> pixels;  // width * height * channels * sampleBytes(type)
  std::vector<std::pair<std::string, std::string>> text;
  /// EXR only: the file's channels that were not read, by name. readExr reads
  /// R, G, B, A (as many as are there in that order), or a file's only channel
  /// whatever its name (Z, Y, depth...); anything else is listed here, so a
  /// caller that needs one channel can refuse a file with more.
  std::vector<std::string> channelsNotRead;

  Image() = default;
  Image(uint32_t w, uint32_t h, uint32_t c, SampleType t)
      : width(w), height(h), channels(c), type(t), pixels(size_t(w) * h * c * sampleBytes(t), 0) {}
  size_t rowBytes() const { return size_t(width) * channels * sampleBytes(type); }
  template <typename T>
  T* row(uint32_t y) { return reinterpret_cast<T*>(pixels.data() + y * rowBytes()); }
  template <typename T>
  const T* row(uint32_t y) const { return reinterpret_cast<const T*>(pixels.data() + y * rowBytes()); }
  /// Value of a text entry, or "" if absent.
  std::string textValue(const std::string& key) const;
};

/// The zlib level PNGs are written at unless told otherwise: libpng's and
/// OpenImageIO's default.
inline constexpr int kDefaultPngZlibLevel = 6;

/// The largest PNG side vox writes and reads: libpng's default limit (1e6),
/// which vox keeps. The format allows 2^31 - 1, but a wider file written by
/// vox's own encoder could not be read back by vox (nor by most viewers).
inline constexpr uint32_t kMaxPngSide = 1000000;
/// Every PNG writer's first check, before anything is computed or written:
/// throws vox::Error (Usage) naming the output (outputName(path)), the side
/// (width or height) and kMaxPngSide when a side is past kMaxPngSide.
void requirePngSides(uint32_t width, uint32_t height, const std::string& path);

/// PNG: U8 or U16 samples, 1..4 channels (gray, gray+alpha, RGB, RGBA), sides
/// at most kMaxPngSide (requirePngSides). `zlibLevel` 0..9. Throws vox::Error (Io).
void writePng(const Image& image, const std::string& path, int zlibLevel = kDefaultPngZlibLevel);
/// writePng's bytes for an image given row by row: `row(y)` returns row y
/// (width * channels * sample bytes, valid until the next call), called for
/// y = 0, 1, ... in order, so the image need never be in memory at once.
void writePngRows(uint32_t width, uint32_t height, uint32_t channels, SampleType type,
                  const std::vector<std::pair<std::string, std::string>>& text, const std::string& path, int zlibLevel,
                  const std::function<const uint8_t*(uint32_t y)>& row);
/// The same PNG content as writePng (SUB-filtered scanlines, zlib `zlibLevel`;
/// runs of >= 4 KiB of zero bytes with zlib's Z_RLE strategy, which codes them
/// the same way faster), deflated in up to 16 row slices on `threads` threads
/// (formats/image/image_png_parallel.cpp). Sides past kMaxPngSide are refused
/// before any work or output (requirePngSides), as libpng refuses them.
/// The bytes depend on the image only, not on `threads`; they differ from
/// writePng's (one deflate stream) but decode to the same pixels.
void writePngParallel(const Image& image, const std::string& path, int zlibLevel, unsigned threads);
/// writePngParallel for an indexed-colour PNG: `indices` is 1-channel U8, each
/// sample an index into `palette` (1..256 sRGB colours, the PLTE chunk).
void writeIndexedPngParallel(const Image& indices, const std::vector<std::array<uint8_t, 3>>& palette,
                             const std::string& path, int zlibLevel, unsigned threads);
/// Reads 8/16-bit gray/GA/RGB/RGBA PNGs (palette and < 8-bit images are expanded
/// to 8 bits). Throws vox::Error (BadInput) naming the file.
Image readPng(const std::string& path);

enum class ExrCompression { None, Zip, Zips, Piz, Rle };
/// EXR: U32 (UINT), F16 (HALF) or F32 (FLOAT), 1..4 channels named R, G, B, A
/// (1 channel: R only; 2: R, G). Throws vox::Error (Io).
/// `threads` > 1 compresses the scanline blocks on OpenEXR's worker pool
/// (grown to `threads` workers on first use, process-wide, never shrunk);
/// blocks are written in order, so the bytes do not depend on `threads`.
void writeExr(const Image& image, const std::string& path, ExrCompression compression = ExrCompression::Zip,
              unsigned threads = 1);
/// Reads an EXR written by writeExr (scanline, channels R[G[B[A]]] of one type).
Image readExr(const std::string& path);

/// True if the file starts with the PNG / EXR magic number.
bool isPngFile(const std::string& path);
bool isExrFile(const std::string& path);

}  // namespace vox
