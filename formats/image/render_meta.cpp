#include "formats/image/render_meta.h"

#include <nlohmann/json.hpp>

#include "libvox/core/error.h"

namespace vox {

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& name, const std::string& what) {
  throwBadInput(name + ": its \"" + kRenderMetaKey + "\" entry " + what);
}

const json& member(const json& object, const char* key, const std::string& name) {
  if (!object.contains(key)) bad(name, std::string("has no \"") + key + "\"");
  return object[key];
}

double number(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_number()) bad(name, where + " must be a number");
  return j.get<double>();
}

int64_t integer(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_number_integer()) bad(name, where + " must be an integer");
  return j.get<int64_t>();
}

template <size_t N>
std::array<double, N> numbers(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_array() || j.size() != N) bad(name, where + " must be " + std::to_string(N) + " numbers");
  std::array<double, N> out;
  for (size_t i = 0; i < N; ++i) out[i] = number(j[i], name, where + "[" + std::to_string(i) + "]");
  return out;
}

uint32_t extent(const json& j, const std::string& name, const std::string& where) {
  const int64_t v = integer(j, name, where);
  if (v < 1 || v > int64_t(UINT32_MAX)) bad(name, where + " must be a positive 32-bit integer");
  return uint32_t(v);
}

}  // namespace

std::string renderMetaJson(const RenderMeta& m) {
  json meta = {{"mode", renderModeName(m.mode)},
               {"scene", m.scene},
               {"dims", {m.dims.x, m.dims.y, m.dims.z}},
               {"origin", m.origin},
               {"voxel_size", m.voxelSize},
               {"view", m.view},
               {"camera", {{"viewMatrix", m.viewMatrix},
                           {"projectionMatrix", m.projectionMatrix},
                           {"imageSize", {{"width", m.width}, {"height", m.height}}}}}};
  if (m.bits) meta["bits"] = *m.bits;
  if (m.level) meta["level"] = *m.level;
  return meta.dump();
}

RenderMeta parseRenderMeta(const std::string& text, const std::string& name) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error&) {
    bad(name, "is not valid JSON");
  }
  if (!j.is_object()) bad(name, "is not a JSON object");
  RenderMeta m;
  const json& mode = member(j, "mode", name);
  const std::optional<RenderMode> parsedMode = mode.is_string() ? renderModeNamed(mode.get<std::string>()) : std::nullopt;
  if (!parsedMode) bad(name, "mode must be one of canonical, class, shaded, depth, normal");
  m.mode = *parsedMode;
  const json& scene = member(j, "scene", name);
  if (!scene.is_string()) bad(name, "scene must be a string");
  m.scene = scene.get<std::string>();
  const json& dims = member(j, "dims", name);
  if (!dims.is_array() || dims.size() != 3) bad(name, "dims must be 3 integers");
  m.dims = {extent(dims[0], name, "dims[0]"), extent(dims[1], name, "dims[1]"), extent(dims[2], name, "dims[2]")};
  m.origin = numbers<3>(member(j, "origin", name), name, "origin");
  m.voxelSize = number(member(j, "voxel_size", name), name, "voxel_size");
  m.view = int(integer(member(j, "view", name), name, "view"));
  const json& camera = member(j, "camera", name);
  if (!camera.is_object()) bad(name, "camera must be an object");
  m.viewMatrix = numbers<16>(member(camera, "viewMatrix", name), name, "camera.viewMatrix");
  m.projectionMatrix = numbers<16>(member(camera, "projectionMatrix", name), name, "camera.projectionMatrix");
  const json& size = member(camera, "imageSize", name);
  if (!size.is_object()) bad(name, "camera.imageSize must be {\"width\": W, \"height\": H}");
  m.width = extent(member(size, "width", name), name, "camera.imageSize.width");
  m.height = extent(member(size, "height", name), name, "camera.imageSize.height");
  if (j.contains("bits")) {
    const int64_t bits = integer(j["bits"], name, "bits");
    if (bits != 8 && bits != 16 && bits != 32) bad(name, "bits must be 8, 16 or 32");
    m.bits = int(bits);
  }
  if (j.contains("level")) {
    const int64_t level = integer(j["level"], name, "level");
    if (level < 0) bad(name, "level must not be negative");
    m.level = int(level);
  }
  return m;
}

std::optional<RenderMeta> readRenderMeta(const Image& image, const std::string& name) {
  const std::string text = image.textValue(kRenderMetaKey);
  if (text.empty()) return std::nullopt;
  return parseRenderMeta(text, name);
}

Camera renderCamera(const RenderMeta& meta, const Image& image, const std::string& name) {
  return Camera::make(meta.viewMatrix, meta.projectionMatrix, image.width, image.height,
                      name + ": \"" + kRenderMetaKey + "\" camera");
}

void requireCanonicalImage(const Image& image, const std::string& name) {
  if (image.channels != 4 ||
      !(image.type == SampleType::U8 || image.type == SampleType::U16 || image.type == SampleType::U32))
    throwBadInput(name + ": a canonical image is RGBA with 8, 16 or 32-bit unsigned samples; this one has " +
                  std::to_string(image.channels) + " channel(s) of " + sampleTypeName(image.type));
}

uint64_t canonicalFullScale(const Image& image) {
  return image.type == SampleType::U8 ? 0xff : image.type == SampleType::U16 ? 0xffff : 0xffffffffull;
}

std::array<uint64_t, 4> canonicalSamples(const Image& image, size_t index) {
  std::array<uint64_t, 4> v{};
  for (size_t c = 0; c < 4; ++c) {
    const size_t k = index * 4 + c;
    switch (image.type) {
      case SampleType::U8: v[c] = image.pixels[k]; break;
      case SampleType::U16: v[c] = reinterpret_cast<const uint16_t*>(image.pixels.data())[k]; break;
      default: v[c] = reinterpret_cast<const uint32_t*>(image.pixels.data())[k]; break;
    }
  }
  return v;
}

}  // namespace vox
