// The PNG reader's fast path: the PNGs vox and most tools write (8- or 16-bit
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
// Internal to formats/image. Thread-safe: no shared state.
#pragma once

#include <cstddef>
#include <cstdint>

#include "formats/image/image.h"

namespace vox {

/// Decodes the PNG in `data` (`size` bytes, signature included) into `out`
/// (rows top first, samples native-endian, tEXt entries in file order) and
/// returns true; returns false, `out` unspecified, when the file is not one
/// the fast path handles or not well formed. The caller has already refused
/// implausible sizes and chunks past the end (image_png.cpp).
bool decodePngFast(const uint8_t* data, size_t size, Image& out);

}  // namespace vox
