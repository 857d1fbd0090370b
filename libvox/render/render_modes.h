// The images render-canonical makes from one cast (castView's hits): one
// function per mode, each a pure function of the hits and what the mode reads.
//
//   canonical  RGBA, RGB = grid coordinates (u, v, w) of the voxel hit, alpha =
//              full scale; a miss is (0, 0, 0, 0). The narrowest exact sample
//              type for the grid (canonicalBits).
//   class      RGBA8: the display colour of the voxel's winning class, alpha
//              255; a miss is transparent.
//   color      RGBA8: the voxel's own colour (linear in the scene, written
//              sRGB-encoded), or its class's display colour where it has
//              none; alpha 255; a miss is transparent.
//   shaded     RGB8: the terrain shading (terrainShade) of the class's palette
//              colour for the face entered (or, with ShadeColor::Voxel, of
//              the voxel's colour where it has one); a miss is the sky colour.
//   depth      one float: the world distance to the entry point; a miss is +inf.
//   normal     RGBA8: the entry face's outward normal, -1/0/+1 as 0/128/255.
// formats/image/RENDER.md specifies them as files.
//
// Pixels are row-major with row 0 at the top, channels interleaved, samples
// native-endian: the layout of vox::Image (formats/image/image.h), which
// wraps them without copying.
//
// Thread safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "libvox/core/classes.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/render/render.h"
#include "libvox/render/touched_voxels.h"

namespace vox {

enum class RenderMode { Canonical, Class, Shaded, Depth, Normal, Color };

/// Every mode, in the order they are listed to users.
inline constexpr std::array<RenderMode, 6> kRenderModes{RenderMode::Canonical, RenderMode::Class, RenderMode::Color,
                                                        RenderMode::Shaded,    RenderMode::Depth, RenderMode::Normal};

/// What the shaded mode lights: the class's palette colour (the block-map
/// renderer's look, the default) or the voxel's own colour where it has one.
enum class ShadeColor { Class, Voxel };

/// "canonical", "class", "color", "shaded", "depth", "normal": the names in files and options.
const char* renderModeName(RenderMode mode);
/// The mode named `name` (exactly as renderModeName spells it), if any.
std::optional<RenderMode> renderModeNamed(std::string_view name);

/// Whether the mode reads the hit voxels' summary bytes (their class).
bool modeNeedsClasses(RenderMode mode);
/// Whether the mode reads the hit voxels' colours (color; shaded with ShadeColor::Voxel).
bool modeNeedsColors(RenderMode mode, ShadeColor shadeColor);

enum class PixelSample { U8, U16, U32, F32 };

/// A mode's pixels: width x height x channels samples of type `sample`.
struct ModeImage {
  uint32_t width = 0, height = 0, channels = 0;
  PixelSample sample = PixelSample::U8;
  std::vector<uint8_t> pixels;
};

/// The sample type a mode's image has (canonical: by `canonicalBits`).
PixelSample modeSample(RenderMode mode, int canonicalBits);
/// The channels a mode's image has: 1 (depth), 3 (shaded) or 4.
uint32_t modeChannels(RenderMode mode);

/// Canonical sample width: the narrowest exact one holding every coordinate of
/// `dims` (max axis - 1 <= 255: 8 bits, <= 65535: 16 bits, else 32 bits).
int canonicalBits(const Dims& dims);

/// The class of each voxel a view hit: summary bytes in TouchedVoxels order.
struct HitSummaries {
  const TouchedVoxels* voxels = nullptr;
  std::span<const SummaryTexel> summaries;  // summaries[i] is voxels->voxel(i)'s
  const SummaryTexel& of(const PixelHit& hit) const { return summaries[voxels->indexOf(hit)]; }
};

/// A voxel's colour as displayed: 8-bit sRGB, alpha 255 when the voxel has a
/// colour and 0 when it has none (the page files' per-voxel colour bytes).
using VoxelColor8 = std::array<uint8_t, 4>;

/// The colour of each voxel a view hit, in TouchedVoxels order.
struct HitColors {
  const TouchedVoxels* voxels = nullptr;
  std::span<const VoxelColor8> colors;  // colors[i] is voxels->voxel(i)'s
  const VoxelColor8* of(const PixelHit& hit) const {
    if (colors.empty()) return nullptr;
    const VoxelColor8& c = colors[voxels->indexOf(hit)];
    return c[3] ? &c : nullptr;
  }
};

/// What the modes read beyond the hits. `summaries` and `classes` are needed by
/// the class, color and shaded modes only (modeNeedsClasses); `colors` by the
/// modes modeNeedsColors names (empty: no voxel has a colour).
struct ModeSources {
  const Camera* camera = nullptr;  // the camera the hits were cast with
  int canonicalBits = 8;
  const ClassTable* classes = nullptr;
  HitSummaries summaries;
  HitColors colors;
  ShadeColor shadeColor = ShadeColor::Class;
};

/// The image of `mode` for `hits`.
ModeImage renderModeImage(RenderMode mode, const ViewHits& hits, const ModeSources& sources);

ModeImage canonicalImage(const ViewHits& hits, int canonicalBits);
ModeImage classImage(const ViewHits& hits, const ClassTable& classes, const HitSummaries& summaries);
ModeImage colorImage(const ViewHits& hits, const ClassTable& classes, const HitSummaries& summaries,
                     const HitColors& colors);
/// With ShadeColor::Voxel, a voxel with a colour is lit from that colour's
/// sRGB bytes / 255 on every face (as a class palette's bytes are), so a voxel
/// coloured like its class's display colour shades like the class.
ModeImage shadedImage(const ViewHits& hits, const Camera& camera, const ClassTable& classes,
                      const HitSummaries& summaries, ShadeColor shadeColor = ShadeColor::Class,
                      const HitColors& colors = {});
ModeImage depthImage(const ViewHits& hits);
ModeImage normalImage(const ViewHits& hits, const Camera& camera);

/// The terrain shading of one face: `base` (linear 0..1 RGB, the block's
/// palette colour for that face) times ambient (sky/horizon by normal y) plus
/// the sun's diffuse term; result not clamped.
std::array<double, 3> terrainShade(const std::array<double, 3>& base, const std::array<int, 3>& normal);
/// The terrain shading's clear colour (sky blue).
inline constexpr std::array<double, 3> kSkyColor{0.53, 0.81, 0.92};

/// The palette colour of class `info` for a face with outward normal `normal`:
/// top for +y, bottom for -y, side otherwise (the block-map format's face
/// slots), from the class's face palette, or its display colour when it has
/// none; 8-bit values / 255. Mid grey for an unknown class.
std::array<double, 3> facePaletteColor(const ClassInfo* info, const std::array<int, 3>& normal);

/// The outward normal of a hit: its entry face, or, when the ray started inside
/// the voxel, the face facing the ray's dominant axis.
std::array<int, 3> hitNormal(const PixelHit& hit, const Vec3d& rayDirection);

}  // namespace vox
