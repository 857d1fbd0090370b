#include "libvox/render/render_modes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vox {

const char* renderModeName(RenderMode mode) {
  switch (mode) {
    case RenderMode::Canonical: return "canonical";
    case RenderMode::Class: return "class";
    case RenderMode::Color: return "color";
    case RenderMode::Shaded: return "shaded";
    case RenderMode::Depth: return "depth";
    case RenderMode::Normal: return "normal";
  }
  return "";
}

std::optional<RenderMode> renderModeNamed(std::string_view name) {
  for (RenderMode m : kRenderModes)
    if (name == renderModeName(m)) return m;
  return std::nullopt;
}

bool modeNeedsClasses(RenderMode mode) {
  return mode == RenderMode::Class || mode == RenderMode::Color || mode == RenderMode::Shaded;
}

bool modeNeedsColors(RenderMode mode, ShadeColor shadeColor) {
  return mode == RenderMode::Color || (mode == RenderMode::Shaded && shadeColor == ShadeColor::Voxel);
}

PixelSample modeSample(RenderMode mode, int canonicalBits) {
  switch (mode) {
    case RenderMode::Canonical:
      return canonicalBits == 8 ? PixelSample::U8 : canonicalBits == 16 ? PixelSample::U16 : PixelSample::U32;
    case RenderMode::Depth: return PixelSample::F32;
    default: return PixelSample::U8;
  }
}

uint32_t modeChannels(RenderMode mode) {
  switch (mode) {
    case RenderMode::Shaded: return 3;
    case RenderMode::Depth: return 1;
    default: return 4;
  }
}

int canonicalBits(const Dims& dims) {
  const uint64_t maxCoord = uint64_t(dims.maxAxis()) - 1;
  return maxCoord <= 255 ? 8 : maxCoord <= 65535 ? 16 : 32;
}

namespace {

size_t sampleBytes(PixelSample s) { return s == PixelSample::U8 ? 1 : s == PixelSample::U16 ? 2 : 4; }

ModeImage blankImage(const ViewHits& hits, uint32_t channels, PixelSample sample) {
  ModeImage img;
  img.width = hits.width;
  img.height = hits.height;
  img.channels = channels;
  img.sample = sample;
  img.pixels.assign(size_t(hits.width) * hits.height * channels * sampleBytes(sample), 0);
  return img;
}

template <typename Sample>
void writeCanonical(ModeImage& img, const ViewHits& hits, Sample fullScale) {
  Sample* px = reinterpret_cast<Sample*>(img.pixels.data());
  for (size_t i = 0; i < hits.pixels.size(); ++i) {
    const PixelHit& p = hits.pixels[i];
    if (!p.hit) continue;
    px[i * 4 + 0] = Sample(p.u);
    px[i * 4 + 1] = Sample(p.v);
    px[i * 4 + 2] = Sample(p.w);
    px[i * 4 + 3] = fullScale;
  }
}

// The world-space direction of pixel i's ray, for the face a ray started inside of.
Vec3d pixelDirection(const Camera& camera, size_t i) {
  Vec3d origin, direction;
  camera.pixelRay(uint32_t(i % camera.width), uint32_t(i / camera.width), origin, direction);
  return direction;
}

}  // namespace

ModeImage canonicalImage(const ViewHits& hits, int bits) {
  const PixelSample sample = modeSample(RenderMode::Canonical, bits);
  ModeImage img = blankImage(hits, 4, sample);
  if (sample == PixelSample::U8) writeCanonical<uint8_t>(img, hits, 0xff);
  else if (sample == PixelSample::U16) writeCanonical<uint16_t>(img, hits, 0xffff);
  else writeCanonical<uint32_t>(img, hits, 0xffffffffu);
  return img;
}

ModeImage classImage(const ViewHits& hits, const ClassTable& classes, const HitSummaries& summaries) {
  ModeImage img = blankImage(hits, 4, PixelSample::U8);
  for (size_t i = 0; i < hits.pixels.size(); ++i) {
    const PixelHit& p = hits.pixels[i];
    if (!p.hit) continue;
    const ClassInfo* info = classes.find(summaries.of(p).cls);
    const Rgb8 c = info ? info->color : Rgb8{128, 128, 128};
    uint8_t* px = img.pixels.data() + i * 4;
    px[0] = c.r, px[1] = c.g, px[2] = c.b, px[3] = 255;
  }
  return img;
}

ModeImage colorImage(const ViewHits& hits, const ClassTable& classes, const HitSummaries& summaries,
                     const HitColors& colors) {
  ModeImage img = blankImage(hits, 4, PixelSample::U8);
  for (size_t i = 0; i < hits.pixels.size(); ++i) {
    const PixelHit& p = hits.pixels[i];
    if (!p.hit) continue;
    uint8_t* px = img.pixels.data() + i * 4;
    if (const VoxelColor8* c = colors.of(p)) {
      px[0] = (*c)[0], px[1] = (*c)[1], px[2] = (*c)[2];
    } else {
      const ClassInfo* info = classes.find(summaries.of(p).cls);
      const Rgb8 c8 = info ? info->color : Rgb8{128, 128, 128};
      px[0] = c8.r, px[1] = c8.g, px[2] = c8.b;
    }
    px[3] = 255;
  }
  return img;
}

ModeImage shadedImage(const ViewHits& hits, const Camera& camera, const ClassTable& classes,
                      const HitSummaries& summaries, ShadeColor shadeColor, const HitColors& colors) {
  ModeImage img = blankImage(hits, modeChannels(RenderMode::Shaded), PixelSample::U8);
  // No sRGB curve: the terrain shading writes its linear result as is.
  auto toByte = [](double c) { return uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); };
  for (size_t i = 0; i < hits.pixels.size(); ++i) {
    const PixelHit& p = hits.pixels[i];
    std::array<double, 3> c = kSkyColor;
    if (p.hit) {
      const std::array<int, 3> n = hitNormal(p, pixelDirection(camera, i));
      const VoxelColor8* own = shadeColor == ShadeColor::Voxel ? colors.of(p) : nullptr;
      const std::array<double, 3> base =
          own ? std::array<double, 3>{(*own)[0] / 255.0, (*own)[1] / 255.0, (*own)[2] / 255.0}
              : facePaletteColor(classes.find(summaries.of(p).cls), n);
      c = terrainShade(base, n);
    }
    uint8_t* px = img.pixels.data() + i * 3;
    for (int k = 0; k < 3; ++k) px[k] = toByte(c[size_t(k)]);
  }
  return img;
}

ModeImage depthImage(const ViewHits& hits) {
  ModeImage img = blankImage(hits, modeChannels(RenderMode::Depth), PixelSample::F32);
  float* px = reinterpret_cast<float*>(img.pixels.data());
  for (size_t i = 0; i < hits.pixels.size(); ++i)
    px[i] = hits.pixels[i].hit ? hits.pixels[i].depth : std::numeric_limits<float>::infinity();
  return img;
}

ModeImage normalImage(const ViewHits& hits, const Camera& camera) {
  ModeImage img = blankImage(hits, 4, PixelSample::U8);
  for (size_t i = 0; i < hits.pixels.size(); ++i) {
    const PixelHit& p = hits.pixels[i];
    if (!p.hit) continue;
    const std::array<int, 3> n = hitNormal(p, pixelDirection(camera, i));
    uint8_t* px = img.pixels.data() + i * 4;
    for (int k = 0; k < 3; ++k) px[k] = uint8_t(n[size_t(k)] < 0 ? 0 : n[size_t(k)] > 0 ? 255 : 128);
    px[3] = 255;
  }
  return img;
}

ModeImage renderModeImage(RenderMode mode, const ViewHits& hits, const ModeSources& sources) {
  switch (mode) {
    case RenderMode::Canonical: return canonicalImage(hits, sources.canonicalBits);
    case RenderMode::Class: return classImage(hits, *sources.classes, sources.summaries);
    case RenderMode::Color: return colorImage(hits, *sources.classes, sources.summaries, sources.colors);
    case RenderMode::Shaded:
      return shadedImage(hits, *sources.camera, *sources.classes, sources.summaries, sources.shadeColor,
                         sources.colors);
    case RenderMode::Depth: return depthImage(hits);
    case RenderMode::Normal: return normalImage(hits, *sources.camera);
  }
  return {};
}

std::array<double, 3> terrainShade(const std::array<double, 3>& base, const std::array<int, 3>& normal) {
  // terrain.wgsl: sunDir = normalize(-0.4, -0.85, -0.5); diffuse = max(dot(n, -sunDir), 0) * sunColor;
  // skyFactor = clamp(n.y * 0.5 + 0.5, 0, 1); ambient = mix(horizon, sky, skyFactor) * 0.55.
  const double sl = std::sqrt(0.4 * 0.4 + 0.85 * 0.85 + 0.5 * 0.5);
  const double sun[3] = {-0.4 / sl, -0.85 / sl, -0.5 / sl};
  const double sunColor[3] = {1.0, 0.97, 0.9};
  const double horizon[3] = {0.18, 0.16, 0.12};
  const double n[3] = {double(normal[0]), double(normal[1]), double(normal[2])};
  const double diffuse = std::max(-(n[0] * sun[0] + n[1] * sun[1] + n[2] * sun[2]), 0.0);
  const double skyFactor = std::clamp(n[1] * 0.5 + 0.5, 0.0, 1.0);
  std::array<double, 3> out;
  for (int c = 0; c < 3; ++c) {
    const double ambient = (horizon[c] * (1.0 - skyFactor) + kSkyColor[size_t(c)] * skyFactor) * 0.55;
    out[size_t(c)] = base[size_t(c)] * (ambient + diffuse * sunColor[c]);
  }
  return out;
}

std::array<double, 3> facePaletteColor(const ClassInfo* info, const std::array<int, 3>& normal) {
  if (!info) return {0.5, 0.5, 0.5};
  Rgb8 c = info->color;
  if (info->faces) c = normal[1] > 0 ? info->faces->top : normal[1] < 0 ? info->faces->bottom : info->faces->side;
  return {c.r / 255.0, c.g / 255.0, c.b / 255.0};
}

std::array<int, 3> hitNormal(const PixelHit& hit, const Vec3d& dir) {
  std::array<int, 3> n{0, 0, 0};
  if (hit.faceAxis >= 0) {
    n[size_t(hit.faceAxis)] = hit.faceSign;
    return n;
  }
  int a = 0;
  for (int i = 1; i < 3; ++i)
    if (std::fabs(dir[size_t(i)]) > std::fabs(dir[size_t(a)])) a = i;
  n[size_t(a)] = dir[size_t(a)] > 0 ? -1 : 1;
  return n;
}

}  // namespace vox
