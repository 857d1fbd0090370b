// Decoding a PNG held in memory (a reference image embedded in JSON as base64,
// such as the block-map format's metadata.json `rgbBase64`). Defined in
// formats/image/image_png.cpp beside readPng, with the same conversions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "formats/image/image.h"

namespace vox {

/// Decodes the PNG in [data, data + size) like readPng. Throws vox::Error
/// (BadInput) naming `name` when the bytes are not a PNG or are corrupt.
Image readPngMemory(const uint8_t* data, size_t size, const std::string& name);

}  // namespace vox
