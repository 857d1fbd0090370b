// Render files (formats/image/RENDER.md): the `vox:canonical` entry every
// render-canonical image carries (a PNG tEXt chunk or an EXR string
// attribute holding one JSON object), and the pixels of canonical renders.
//
// One writer (renderMetaJson) and one reader (parseRenderMeta): the reader
// accepts exactly what the writer writes and names the element it refuses.
//
// Thread safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "formats/image/image.h"
#include "libvox/core/types.h"
#include "libvox/render/camera.h"
#include "libvox/render/render_modes.h"
#include "libvox/render/view_framing.h"

namespace vox {

/// The image text key of the entry.
inline constexpr const char* kRenderMetaKey = "vox:canonical";

/// What a render was made from: enough to check or pick it without its command line.
struct RenderMeta {
  RenderMode mode = RenderMode::Canonical;
  std::string scene;                      // the input's path, as given
  Dims dims;                              // the grid's extent in voxels
  std::array<double, 3> origin{0, 0, 0};  // world position of grid point (0, 0, 0)
  double voxelSize = 1;                   // world units per voxel
  int view = 0;                           // the view's index in its camera file (0 for --eye)
  Mat4d viewMatrix{}, projectionMatrix{};  // column-major, the block-map format's conventions
  uint32_t width = 0, height = 0;          // the image size the camera was made for
  std::optional<int> bits;                // canonical renders: bits per sample (8, 16 or 32)
  std::optional<int> level;               // renders of a page file: the level rendered
  std::optional<LookAtCamera> lookAt;     // a camera vox chose (a named view, an orbit): its look-at form
  bool operator==(const RenderMeta&) const = default;
};

/// The entry's text: one JSON object with sorted keys, no whitespace.
std::string renderMetaJson(const RenderMeta& meta);

/// Parses an entry's text; throws vox::Error (BadInput) naming `name` (the
/// image file) and the element that is missing or malformed.
RenderMeta parseRenderMeta(const std::string& text, const std::string& name);

/// The image's entry, if it has one (same errors as parseRenderMeta).
std::optional<RenderMeta> readRenderMeta(const Image& image, const std::string& name);

/// The camera the render was made with; throws vox::Error (BadInput) naming
/// `name` when the matrices make no camera, or when `image` is not the size
/// the entry was made for (cropped or resized after rendering: the matrices no
/// longer give its pixels' rays), a message that ends with `fix` (what to do
/// instead: give a camera for the image as it is).
Camera renderCamera(const RenderMeta& meta, const Image& image, const std::string& name, const std::string& fix);

/// Canonical renders are RGBA of 8, 16 or 32-bit unsigned samples; throws
/// vox::Error (BadInput) naming `name` when `image` is not.
void requireCanonicalImage(const Image& image, const std::string& name);
/// The alpha of a hit in `image`'s sample type: 2^bits - 1.
uint64_t canonicalFullScale(const Image& image);
/// The four samples (R, G, B, A) of pixel `index` (row-major) of a canonical image.
std::array<uint64_t, 4> canonicalSamples(const Image& image, size_t index);

}  // namespace vox
