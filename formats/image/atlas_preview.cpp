#include "formats/image/atlas_preview.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "formats/core/json_text.h"
#include "libvox/core/error.h"
#include "libvox/core/version.h"

namespace vox {

namespace {

// Viridis at 0, 1/8, ..., 1 (matplotlib's table, 8-bit).
constexpr uint8_t kStops[9][3] = {{68, 1, 84},    {71, 45, 123},  {59, 82, 139},  {44, 114, 142}, {33, 145, 140},
                                  {40, 174, 128}, {94, 201, 98},  {173, 220, 48}, {253, 231, 37}};
constexpr int kStopAt[9] = {0, 32, 64, 96, 128, 160, 192, 224, 255};

// Sample i of any sample type, as an unsigned integer (floats truncated).
uint64_t sampleU(const Image& img, size_t i) {
  switch (img.type) {
    case SampleType::U8: return img.pixels[i];
    case SampleType::U16: return reinterpret_cast<const uint16_t*>(img.pixels.data())[i];
    case SampleType::U32: return reinterpret_cast<const uint32_t*>(img.pixels.data())[i];
    case SampleType::F16: return reinterpret_cast<const uint16_t*>(img.pixels.data())[i];  // bits: 0 = +0
    case SampleType::F32: return reinterpret_cast<const uint32_t*>(img.pixels.data())[i];
  }
  return 0;
}

// round(a * 255 / b) half up, for 0 <= a <= b, b > 0.
uint8_t scale255(uint64_t a, uint64_t b) { return uint8_t((2 * a * 255 + b) / (2 * b)); }

void put(uint8_t* p, const std::array<uint8_t, 3>& c) { p[0] = c[0], p[1] = c[1], p[2] = c[2]; }

}  // namespace

uint8_t grayRamp(uint8_t index) { return uint8_t(48 + (207 * index + 127) / 255); }

std::array<uint8_t, 3> ramp(uint8_t index) {
  int s = 0;
  while (s < 7 && index > kStopAt[s + 1]) ++s;
  const int v0 = kStopAt[s], v1 = kStopAt[s + 1], d = v1 - v0, t = index - v0;
  std::array<uint8_t, 3> c{};
  for (int k = 0; k < 3; ++k) c[size_t(k)] = uint8_t((kStops[s][k] * (d - t) + kStops[s + 1][k] * t + d / 2) / d);
  return c;
}

std::string previewPath(const std::string& atlasPath) {
  const size_t slash = atlasPath.find_last_of('/');
  const size_t dot = atlasPath.find_last_of('.');
  const std::string stem = dot == std::string::npos || (slash != std::string::npos && dot < slash) ? atlasPath
                                                                                                 : atlasPath.substr(0, dot);
  return stem + ".preview.png";
}

std::array<uint8_t, 3> AtlasPreview::rgb(uint32_t x, uint32_t y) const {
  const size_t i = size_t(y) * image.width + x;
  if (!palette.empty()) return palette[image.pixels[i]];
  if (image.channels == 1) return {image.pixels[i], image.pixels[i], image.pixels[i]};
  return {image.pixels[i * 3], image.pixels[i * 3 + 1], image.pixels[i * 3 + 2]};
}

void writeAtlasPreview(const AtlasPreview& preview, const std::string& path, unsigned threads) {
  constexpr int kPreviewZlibLevel = 1;
  if (preview.palette.empty()) writePngParallel(preview.image, path, kPreviewZlibLevel, threads);
  else writeIndexedPngParallel(preview.image, preview.palette, path, kPreviewZlibLevel, threads);
}

AtlasPreview atlasPreview(const Image& atlas, const AtlasImageInfo& info, const ClassTable& classes,
                          const std::string& atlasFileName) {
  const AtlasLayout& L = info.layout;
  const uint32_t W = L.width, H = L.height;
  nlohmann::json meta = {{"atlas", atlasFileName}, {"content", atlasContentName(info.content)}};
  AtlasPreview result;
  Image& out = result.image;
  switch (info.content) {
    case AtlasContent::Summary: {
      // Three panels side by side: class colour | confidence | observations.
      const size_t classEntries = classes.size() + 1;  // + the unknown-class colour
      const size_t levels = 256 - 1 - classEntries;
      if (levels >= 64) {
        auto& pal = result.palette;
        pal.push_back({0, 0, 0});
        std::array<uint8_t, 256> classIndex;
        classIndex.fill(uint8_t(classEntries));  // unknown ids: the last class entry
        for (const ClassInfo& c : classes.classes()) {
          classIndex[c.id] = uint8_t(pal.size());
          pal.push_back({c.color.r, c.color.g, c.color.b});
        }
        pal.push_back({kUnknownClassColor.r, kUnknownClassColor.g, kUnknownClassColor.b});
        const size_t base = pal.size(), L1 = levels - 1;
        for (size_t j = 0; j < levels; ++j) pal.push_back(ramp(uint8_t((2 * j * 255 + L1) / (2 * L1))));
        std::array<uint8_t, 256> rampIndex;
        for (size_t v = 0; v < 256; ++v) rampIndex[v] = uint8_t(base + (2 * v * L1 + 255) / 510);
        out = Image(3 * W, H, 1, SampleType::U8);
        for (uint32_t y = 0; y < H; ++y) {
          const uint8_t* s = atlas.pixels.data() + size_t(y) * W * 4;
          uint8_t* row = out.pixels.data() + size_t(y) * out.width;
          for (uint32_t x = 0; x < W; ++x, s += 4) {
            if (!(s[0] | s[1] | s[2] | s[3])) continue;  // empty: black (index 0)
            row[x] = classIndex[s[0]];
            row[W + x] = rampIndex[s[1]];
            row[2 * W + x] = rampIndex[s[2]];
          }
        }
        meta["ramp_levels"] = levels;
      } else {
        out = Image(3 * W, H, 3, SampleType::U8);
        std::array<std::array<uint8_t, 3>, 256> classColor;
        classColor.fill({kUnknownClassColor.r, kUnknownClassColor.g, kUnknownClassColor.b});
        for (const ClassInfo& c : classes.classes()) classColor[c.id] = {c.color.r, c.color.g, c.color.b};
        for (uint32_t y = 0; y < H; ++y) {
          const uint8_t* s = atlas.pixels.data() + size_t(y) * W * 4;
          uint8_t* row = out.pixels.data() + size_t(y) * out.rowBytes();
          for (uint32_t x = 0; x < W; ++x, s += 4) {
            if (!(s[0] | s[1] | s[2] | s[3])) continue;  // empty: black
            put(row + size_t(x) * 3, classColor[s[0]]);
            put(row + size_t(W + x) * 3, ramp(s[1]));
            put(row + size_t(2 * W + x) * 3, ramp(s[2]));
          }
        }
        meta["ramp_levels"] = 256;
      }
      meta["panels"] = {"left: class colour", "middle: confidence byte 0..255", "right: observations byte 0..255"};
      meta["ramp"] = "viridis, black = empty";
      break;
    }
    case AtlasContent::Identity: {
      out = Image(W, H, 3, SampleType::U8);
      const uint32_t ch = atlas.channels;
      const size_t sb = sampleBytes(atlas.type);
      const uint32_t dims[3] = {L.dims.x, L.dims.y, L.dims.z};
      for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
          const size_t alpha = (size_t(y) * W + x) * ch + ch - 1;
          bool set = false;
          for (size_t k = 0; k < sb; ++k) set |= atlas.pixels[alpha * sb + k] != 0;
          if (!set) continue;
          const auto v = L.toVoxel(info.layer, x, y);
          if (!v) continue;
          const int32_t c[3] = {v->u, v->v, v->w};
          uint8_t* p = out.pixels.data() + (size_t(y) * W + x) * 3;
          for (int a = 0; a < 3; ++a) p[a] = dims[a] > 1 ? scale255(uint64_t(c[a]), dims[a] - 1) : 0;
        }
      meta["channels"] = "RGB = (u, v, w) * 255 / (dims - 1)";
      break;
    }
    case AtlasContent::Color: {
      out = Image(W, H, 3, SampleType::U8);
      for (size_t i = 0, n = size_t(W) * H; i < n; ++i)
        if (atlas.pixels[i * 4 + 3]) std::copy_n(atlas.pixels.data() + i * 4, 3, out.pixels.data() + i * 3);
      meta["channels"] = "RGB = the colour (sRGB), black = none";
      break;
    }
    case AtlasContent::Votes: {
      // Gray, a third of an RGB preview's bytes: one layer per class adds up.
      out = Image(W, H, 1, SampleType::U8);
      const size_t n = size_t(W) * H;
      uint64_t maxVotes = 0;
      for (size_t i = 0; i < n; ++i) maxVotes = std::max(maxVotes, sampleU(atlas, i));
      for (size_t i = 0; i < n; ++i)
        if (const uint64_t v = sampleU(atlas, i)) out.pixels[i] = grayRamp(scale255(v, maxVotes));
      meta["class_id"] = info.classId;
      if (const ClassInfo* c = classes.find(info.classId)) meta["class_name"] = c->name;
      meta["max_votes"] = maxVotes;
      meta["gray"] = "48 + 207 * votes / max_votes (rounded), 0 = no vote";
      break;
    }
    case AtlasContent::Occupancy:
    case AtlasContent::Occupancy2: {
      const int bits = info.content == AtlasContent::Occupancy ? 1 : 2;
      const uint32_t perByte = 8 / uint32_t(bits);
      out = Image(W, H, 1, SampleType::U8);
      for (uint32_t y = 0; y < H; ++y) {
        const uint8_t* row = atlas.pixels.data() + size_t(y) * atlas.width;
        uint8_t* o = out.pixels.data() + size_t(y) * W;
        for (uint32_t x = 0; x < W; ++x) {
          const uint8_t byte = row[x / perByte];
          const int shift = bits * int(x % perByte);
          if (bits == 1) o[x] = ((byte >> shift) & 1) ? 255 : 0;
          else o[x] = uint8_t(85 * (2 * ((byte >> shift) & 1) + ((byte >> (shift + 1)) & 1)));
        }
      }
      meta["gray"] = bits == 1 ? "255 = occupied, 0 = empty" : "0 empty, 85 touched only, 170 occupied, 255 occupied and touched";
      break;
    }
  }
  out.text = {{kPreviewTextKey, jsonText(meta)}, {"Software", versionString()}};
  return result;
}

}  // namespace vox
