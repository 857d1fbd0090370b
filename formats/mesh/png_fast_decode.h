// The PNG decoders' fast path: the PNGs vox and most tools write (8- or 16-bit
// gray, gray + alpha, RGB or RGBA, not interlaced, no transparency chunk),
// inflated with libdeflate instead of libpng's zlib.
//
// Why not libpng alone: zlib 1.2's inflate copies overlapping matches a byte
// at a time, and the images vox reads most (renders' class, normal and depth
// images: large runs of one colour, SUB-filtered) are almost all such
// matches: a 1024^2 RGBA class image took 8.4 ms to inflate with zlib and
// 0.5 ms with libdeflate (docs/bench-fuse.md, "Reading views").
//
// The fast path gives exactly the pixels and text entries libpng's reader
// (image_png.cpp) gives for the same file, and declines everything else:
// palettes, bit depths below 8, interlacing, tRNS, compressed or
// international text, chunks it does not know, any CRC or zlib check that
// fails, data past the image. The caller then reads the file with libpng,
// which decides (and words) whatever is wrong, so errors are libpng's.
//
// Used by the image readers (formats/image/image_png.cpp) and the texture
// decoder (formats/mesh/texture_image.cpp, in place of stb_image's inflate),
// so it lives in the bake tier, below both. Thread-safe: no shared state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vox {

/// A PNG's pixels as the fast path decodes them.
struct DecodedPng {
  uint32_t width = 0, height = 0;
  uint32_t channels = 0;  // 1 gray, 2 gray + alpha, 3 RGB, 4 RGBA
  uint32_t bitDepth = 8;  // 8 or 16
  std::vector<uint8_t> pixels;  // rows top first, channels interleaved, 16-bit samples native-endian
  std::vector<std::pair<std::string, std::string>> text;  // tEXt entries, in file order
};

/// Whose reading the fast path stands in for, and so which chunks it may pass over.
enum class PngReader {
  Libpng,    // image_png.cpp: ancillary chunks libpng reads without a pixel or text change
             // (gAMA, sRGB, cHRM, iCCP, pHYs, oFFs, pCAL, sCAL, tIME, bKGD, sBIT, eXIf) and
             // tEXt, whose entries it returns; any other chunk declines
  StbImage,  // texture_image.cpp: every ancillary chunk but tRNS (stb_image skips them all);
             // no text
};

/// Decodes the PNG in `data` (`size` bytes, signature included) into `out`
/// and returns true; returns false, `out` unspecified, when the file is not
/// one the fast path handles or not well formed (the caller then decodes it
/// its other way, which words what is wrong). Declines images whose pixels
/// the file could not hold compressed (deflate's 1032:1 times libpng's 32:1).
bool decodePngFast(const uint8_t* data, size_t size, DecodedPng& out, PngReader reader = PngReader::Libpng);

/// The first chunk of the PNG in `data` whose CRC fails, worded ("PNG:
/// chunk 'IDAT' at byte 57 fails its CRC"), up to IEND or a chunk cut short;
/// "" when every CRC holds or `data` is not a PNG. For readers that check
/// none (stb_image), so that a damaged file they decode can be said to be.
std::string firstFailedPngCrc(const uint8_t* data, size_t size);

}  // namespace vox
