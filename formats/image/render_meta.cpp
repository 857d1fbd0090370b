#include "formats/image/render_meta.h"

#include <nlohmann/json.hpp>

#include "formats/core/camera_json.h"
#include "formats/core/json_fields.h"
#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

using nlohmann::json;

std::string context(const std::string& name) { return name + ": its \"" + kRenderMetaKey + "\" entry"; }

template <size_t N>
std::array<double, N> numbers(const json& j, const std::string& where, const std::string& element) {
  if (!j.is_array() || j.size() != N) throwBadInput(where + ": " + element + " must be " + std::to_string(N) + " numbers");
  std::array<double, N> out;
  for (size_t i = 0; i < N; ++i) out[i] = jsonNumber(j[i], where, element + "[" + std::to_string(i) + "]");
  return out;
}

uint32_t imageSide(const json& j, const std::string& where, const std::string& element) {
  const int64_t v = jsonInteger(j, where, element);
  if (v < 1 || v > int64_t(kMaxImageSide))
    throwBadInput(where + ": " + element + " must be 1.." + std::to_string(kMaxImageSide));
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
  if (m.lookAt) meta["look_at"] = json::parse(lookAtCameraFileJson({*m.lookAt}));
  return jsonText(meta);
}

RenderMeta parseRenderMeta(const std::string& text, const std::string& name) {
  const std::string where = context(name);
  json j;
  try {
    j = parseJsonInput(text, where);
  } catch (const json::exception&) {  // parse_error, and out_of_range.406 for a number past double's range
    throwBadInput(where + " is not valid JSON");
  }
  if (!j.is_object()) throwBadInput(where + " is not a JSON object");
  RenderMeta m;
  const std::optional<RenderMode> mode = renderModeNamed(jsonString(jsonMember(j, "mode", where), where, "mode"));
  if (!mode) throwBadInput(where + ": mode must be one of canonical, class, color, shaded, depth, normal");
  m.mode = *mode;
  m.scene = jsonString(jsonMember(j, "scene", where), where, "scene");
  m.dims = jsonDims(jsonMember(j, "dims", where), where, "dims");
  m.origin = numbers<3>(jsonMember(j, "origin", where), where, "origin");
  m.voxelSize = jsonNumber(jsonMember(j, "voxel_size", where), where, "voxel_size");
  m.view = int(jsonInteger(jsonMember(j, "view", where), where, "view"));
  const json& camera = jsonMember(j, "camera", where);
  if (!camera.is_object()) throwBadInput(where + ": camera must be an object");
  m.viewMatrix = numbers<16>(jsonMember(camera, "viewMatrix", where), where, "camera.viewMatrix");
  m.projectionMatrix = numbers<16>(jsonMember(camera, "projectionMatrix", where), where, "camera.projectionMatrix");
  const json& size = jsonMember(camera, "imageSize", where);
  if (!size.is_object()) throwBadInput(where + ": camera.imageSize must be {\"width\": W, \"height\": H}");
  m.width = imageSide(jsonMember(size, "width", where), where, "camera.imageSize.width");
  m.height = imageSide(jsonMember(size, "height", where), where, "camera.imageSize.height");
  if (j.contains("bits")) {
    const int64_t bits = jsonInteger(j["bits"], where, "bits");
    if (bits != 8 && bits != 16 && bits != 32) throwBadInput(where + ": bits must be 8, 16 or 32");
    m.bits = int(bits);
  }
  if (j.contains("level")) m.level = int(jsonUnsigned(j["level"], where, "level"));
  if (j.contains("look_at")) {
    const std::vector<CameraView> views = parseCameraJson(j["look_at"].dump(), where + ": look_at", std::nullopt);
    if (views.size() != 1 || !views[0].lookAt) throwBadInput(where + ": look_at must be one look-at camera");
    m.lookAt = views[0].lookAt;
  }
  return m;
}

std::optional<RenderMeta> readRenderMeta(const Image& image, const std::string& name) {
  const std::string text = image.textValue(kRenderMetaKey);
  if (text.empty()) return std::nullopt;
  return parseRenderMeta(text, name);
}

Camera renderCamera(const RenderMeta& meta, const Image& image, const std::string& name, const std::string& fix) {
  // render-canonical writes the image's own size; another one means the image
  // was cropped or resized since (an EXR crop keeps only its data window, and
  // both keep the whole render's entry).
  if (meta.width != image.width || meta.height != image.height)
    throwBadInput(name + " is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                  " but its " + kRenderMetaKey + " camera was made for " + std::to_string(meta.width) + "x" +
                  std::to_string(meta.height) + " (cropped or resized after rendering?); " + fix);
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
