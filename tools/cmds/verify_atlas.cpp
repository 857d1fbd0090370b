// verify-bijection --atlas IMG --scene S: every texel of a built atlas or bitmap
// against its scene, through the inverse mapping (texel -> voxel), so it checks
// the builder's forward placement independently. Reports like idiff: counts,
// the first and the worst failing texel with coordinates in every space and
// both values; exit 1 on any failure.
#include <chrono>
#include <iostream>
#include <unordered_map>

#include "formats/core/json_text.h"
#include "formats/image/atlas_meta.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "libvox/core/texel_formats.h"
#include "tools/cli/verify_bijection.h"

namespace voxcli {

namespace {

uint64_t key(const vox::Coord3& c) {
  return (uint64_t(uint32_t(c.u)) << 42) | (uint64_t(uint32_t(c.v)) << 21) | uint64_t(uint32_t(c.w));
}

std::array<double, 4> readTexel(const vox::Image& img, uint32_t x, uint32_t y) {
  std::array<double, 4> v{0, 0, 0, 0};
  const size_t base = (size_t(y) * img.width + x) * img.channels;
  for (uint32_t c = 0; c < img.channels; ++c) {
    const size_t i = base + c;
    switch (img.type) {
      case vox::SampleType::U8: v[c] = img.pixels[i]; break;
      case vox::SampleType::U16: v[c] = reinterpret_cast<const uint16_t*>(img.pixels.data())[i]; break;
      case vox::SampleType::U32: v[c] = reinterpret_cast<const uint32_t*>(img.pixels.data())[i]; break;
      case vox::SampleType::F16: v[c] = vox::halfToFloat(reinterpret_cast<const uint16_t*>(img.pixels.data())[i]); break;
      case vox::SampleType::F32: v[c] = reinterpret_cast<const float*>(img.pixels.data())[i]; break;
    }
  }
  return v;
}

struct Failure {
  vox::TexelAddress texel;
  std::optional<vox::Coord3> voxel;
  std::array<double, 4> expected, actual;
  double error = 0;
};

nlohmann::json failureJson(const Failure& f, uint32_t channels) {
  nlohmann::json e = nlohmann::json::array(), a = nlohmann::json::array();
  for (uint32_t c = 0; c < channels; ++c) e.push_back(f.expected[c]), a.push_back(f.actual[c]);
  nlohmann::json j = {{"texel", {f.texel.layer, f.texel.x, f.texel.y}}, {"expected", e}, {"actual", a}, {"error", f.error}};
  j["voxel"] = f.voxel ? nlohmann::json{f.voxel->u, f.voxel->v, f.voxel->w} : nlohmann::json(nullptr);
  return j;
}

std::string describe(const Failure& f, uint32_t channels) {
  std::string s = "texel (layer " + std::to_string(f.texel.layer) + ", x " + std::to_string(f.texel.x) + ", y " +
                  std::to_string(f.texel.y) + ") = " + (f.voxel ? "voxel " + vox::toString(*f.voxel) : "padding") +
                  ": expected [";
  for (uint32_t c = 0; c < channels; ++c) s += (c ? ", " : "") + nlohmann::json(f.expected[c]).dump();
  s += "], found [";
  for (uint32_t c = 0; c < channels; ++c) s += (c ? ", " : "") + nlohmann::json(f.actual[c]).dump();
  return s + "]";
}

}  // namespace

int runAtlasCheck(const VerifyBijectionOptions& o) {
  Run run("verify-bijection", o.common);
  run.phase("read");
  run.input(o.atlas);
  run.input(o.scene);
  vox::AtlasImageInfo info;
  const vox::Image img = vox::readAtlasImage(o.atlas, info);
  const vox::Scene scene = vox::readSceneVdb(o.scene);
  const vox::AtlasLayout& L = info.layout;
  if (!(scene.header().dims == L.dims))
    throw vox::Error(vox::ErrorKind::BadInput, o.atlas + ": built for dims " + vox::toString(L.dims) + " but " + o.scene +
                                                   " has " + vox::toString(scene.header().dims));
  // Expected values of occupied voxels, keyed by voxel; everything else expects 0.
  run.phase("expect");
  const vox::TexelFormat idFormat = vox::parseTexelFormat(info.format).value_or(vox::TexelFormat::Rgba8);
  std::unordered_map<uint64_t, std::array<uint64_t, 4>> expected;
  expected.reserve(scene.occupiedCount());
  scene.forEachVoxel([&](const vox::VoxelView& v) {
    expected.emplace(key(v.at), vox::atlasTexel(info.content, &v, idFormat, info.classId));
  });
  run.phase("compare");
  const bool bitmap = info.content == vox::AtlasContent::Occupancy || info.content == vox::AtlasContent::Occupancy2;
  const uint32_t channels = bitmap ? (info.content == vox::AtlasContent::Occupancy ? 1 : 2) : img.channels;
  uint64_t checked = 0, failures = 0, voxelTexels = 0;
  std::optional<Failure> first, worst;
  for (uint32_t y = 0; y < L.height; ++y)
    for (uint32_t x = 0; x < L.width; ++x) {
      const std::optional<vox::Coord3> voxel = L.toVoxel(info.layer, x, y);
      std::array<double, 4> want{0, 0, 0, 0}, got{0, 0, 0, 0};
      if (voxel) {
        ++voxelTexels;
        auto it = expected.find(key(*voxel));
        if (it != expected.end())
          for (int c = 0; c < 4; ++c) want[c] = double(it->second[c]);
      }
      if (bitmap) {
        const uint8_t byte = img.pixels[size_t(y) * img.width + (info.content == vox::AtlasContent::Occupancy ? x >> 3 : x >> 2)];
        if (info.content == vox::AtlasContent::Occupancy) {
          got[0] = (byte >> (x & 7)) & 1;
        } else {
          got[0] = (byte >> (2 * (x & 3))) & 1;
          got[1] = (byte >> (2 * (x & 3) + 1)) & 1;  // touched: any value is allowed at occupied voxels
          want[1] = want[0] > 0 ? got[1] : 0;
        }
      } else {
        got = readTexel(img, x, y);
      }
      ++checked;
      double err = 0;
      for (uint32_t c = 0; c < channels; ++c) err = std::max(err, std::abs(got[c] - want[c]));
      if (err == 0) continue;
      ++failures;
      Failure f{{info.layer, x, y}, voxel, want, got, err};
      if (!first) first = f;
      if (!worst || err > worst->error) worst = f;
    }
  // Bitmap rows may have padding bits past the atlas width: they must be 0.
  if (bitmap) {
    const uint32_t perByte = info.content == vox::AtlasContent::Occupancy ? 8 : 4;
    for (uint32_t y = 0; y < L.height; ++y)
      for (uint32_t x = L.width; x < img.width * perByte; ++x) {
        const uint8_t byte = img.pixels[size_t(y) * img.width + x / perByte];
        const int bitsPer = 8 / int(perByte);
        if ((byte >> (bitsPer * int(x % perByte))) & ((1 << bitsPer) - 1)) {
          ++failures;
          Failure f{{info.layer, x, y}, std::nullopt, {0, 0, 0, 0}, {1, 0, 0, 0}, 1};
          if (!first) first = f;
        }
      }
  }
  nlohmann::json j = {{"atlas", o.atlas},        {"scene", o.scene},       {"content", vox::atlasContentName(info.content)},
                      {"format", info.format},   {"layer", info.layer},    {"texels_checked", checked},
                      {"voxel_texels", voxelTexels}, {"failures", failures}, {"ok", failures == 0}};
  if (first) j["first_failure"] = failureJson(*first, channels);
  if (worst) j["worst_failure"] = failureJson(*worst, channels);
  run.counts() = {{"texels_checked", checked}, {"failures", failures}};
  run.error() = {{"failures", failures}, {"max_error", worst ? worst->error : 0.0}};
  if (o.json) {
    std::cout << vox::jsonText(j, 2) << "\n";
  } else {
    std::cout << o.atlas << " (" << vox::atlasContentName(info.content) << ", " << info.format << ", layer "
              << info.layer << ") against " << o.scene << ": " << counted(checked, "texel", "texels") << " checked, "
              << failures << " differ\n";
    if (first) std::cout << "  first: " << describe(*first, channels) << "\n";
    if (worst) std::cout << "  worst: " << describe(*worst, channels) << "\n";
    std::cout << (failures == 0 ? "OK" : "FAILED") << "\n";
  }
  return run.finish(failures == 0 ? kExitOk : kExitCheckFailed);
}

}  // namespace voxcli
