#include "formats/core/camera_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "formats/core/json_fields.h"
#include "formats/core/json_input.h"
#include "formats/core/json_text.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& name, const std::string& what) { throwBadInput(name + ": " + what); }

double number(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_number()) bad(name, where + " must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) bad(name, where + " must be finite");
  return v;
}

Vec3d vec3(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_array() || j.size() != 3) bad(name, where + " must be an array of 3 numbers");
  return {number(j[0], name, where + "[0]"), number(j[1], name, where + "[1]"), number(j[2], name, where + "[2]")};
}

Mat4d matrix(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_array() || j.size() != 16) bad(name, where + " must be an array of 16 numbers (column-major)");
  Mat4d m;
  for (size_t i = 0; i < 16; ++i) m[i] = number(j[i], name, where + "[" + std::to_string(i) + "]");
  return m;
}

uint32_t side(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_number_integer() || j.get<int64_t>() < 1 || j.get<int64_t>() > int64_t(kMaxImageSide))
    bad(name, where + " must be an integer in 1.." + std::to_string(kMaxImageSide));
  return uint32_t(j.get<int64_t>());
}

CameraView lookAtCamera(const json& c, const std::string& name, const std::string& where, int index,
                        std::optional<std::pair<uint32_t, uint32_t>> size) {
  if (!c.is_object()) bad(name, where + " must be an object with \"eye\" and \"target\"");
  if (!c.contains("eye") || !c.contains("target")) bad(name, where + " needs \"eye\" and \"target\"");
  jsonOnlyKeys(c, {"eye", "target", "up", "fov", "size", "view"}, name, where);
  const Vec3d eye = vec3(c["eye"], name, where + ".eye");
  const Vec3d target = vec3(c["target"], name, where + ".target");
  const Vec3d up = c.contains("up") ? vec3(c["up"], name, where + ".up") : kLookAtUp;
  const double fov = c.contains("fov") ? number(c["fov"], name, where + ".fov") : kLookAtFovYDegrees;
  uint32_t w = kDefaultImageSide, h = kDefaultImageSide;
  if (c.contains("size")) {
    const json& s = c["size"];
    if (!s.is_array() || s.size() != 2) bad(name, where + ".size must be [width, height]");
    w = side(s[0], name, where + ".size[0]");
    h = side(s[1], name, where + ".size[1]");
  }
  if (size) std::tie(w, h) = *size;
  std::string chosen;
  if (c.contains("view")) {
    if (!c["view"].is_string()) bad(name, where + ".view must be a string (the view vox chose, e.g. \"front\")");
    chosen = c["view"].get<std::string>();
  }
  CameraView v;
  try {
    v.camera = Camera::lookAt(eye, target, up, fov, w, h);
  } catch (const Error& e) {
    bad(name, where + ": " + withoutCameraLead(e.what()));
  }
  v.lookAt = LookAtCamera{eye, target, up, fov, w, h, chosen};
  v.label = chosen.empty() ? "camera " + std::to_string(index) : chosen;
  v.source = name + ": " + where;
  v.index = index;
  return v;
}

}  // namespace

std::vector<CameraView> parseCameraJson(const std::string& text, const std::string& name,
                                        std::optional<std::pair<uint32_t, uint32_t>> size) {
  json doc;
  try {
    doc = parseJsonInput(text, name);
  } catch (const json::exception& e) {  // parse_error, and out_of_range.406 for a number past double's range
    bad(name, std::string("not valid JSON: ") + e.what());
  }
  if (!doc.is_object()) bad(name, "expected a JSON object (a metadata.json with \"views\", a camera, or \"cameras\")");
  std::vector<CameraView> out;
  if (doc.contains("views")) {
    const json& views = doc["views"];
    if (!views.is_array() || views.empty()) bad(name, "\"views\" must be a non-empty array");
    uint32_t w = 0, h = 0;
    if (doc.contains("imageSize")) {
      const json& s = doc["imageSize"];
      if (!s.is_object() || !s.contains("width") || !s.contains("height"))
        bad(name, "\"imageSize\" must be {\"width\": W, \"height\": H}");
      w = side(s["width"], name, "imageSize.width");
      h = side(s["height"], name, "imageSize.height");
    }
    if (size) std::tie(w, h) = *size;
    if (w == 0) throwBadInput(name + ": no \"imageSize\" in the file: give the image size", Setting::ImageSize);
    for (size_t i = 0; i < views.size(); ++i) {
      const std::string where = "views[" + std::to_string(i) + "]";
      const json& v = views[i];
      if (!v.is_object()) bad(name, where + " must be an object");
      for (const char* key : {"viewMatrix", "projectionMatrix"})
        if (!v.contains(key)) bad(name, where + " has no \"" + key + "\"");
      CameraView cv;
      cv.camera = Camera::make(matrix(v["viewMatrix"], name, where + ".viewMatrix"),
                               matrix(v["projectionMatrix"], name, where + ".projectionMatrix"), w, h,
                               name + ": " + where);
      cv.index = int(i);
      cv.source = name + ": " + where;
      cv.label = "view " + std::to_string(i);
      if (v.contains("id") && v["id"].is_string()) cv.label += " (" + v["id"].get<std::string>() + ")";
      out.push_back(std::move(cv));
    }
    return out;
  }
  if (doc.contains("cameras")) {
    const json& cams = doc["cameras"];
    if (!cams.is_array() || cams.empty()) bad(name, "\"cameras\" must be a non-empty array");
    for (size_t i = 0; i < cams.size(); ++i)
      out.push_back(lookAtCamera(cams[i], name, "cameras[" + std::to_string(i) + "]", int(i), size));
    return out;
  }
  if (doc.contains("eye")) {
    out.push_back(lookAtCamera(doc, name, "camera", 0, size));
    return out;
  }
  bad(name, "expected \"views\" (a block-map metadata.json), \"cameras\", or a camera with \"eye\" and \"target\"");
}

namespace {

json lookAtJson(const LookAtCamera& c) {
  json j = {{"eye", c.eye}, {"target", c.target}, {"up", c.up}, {"fov", c.fovYDegrees}, {"size", {c.width, c.height}}};
  if (!c.view.empty()) j["view"] = c.view;
  return j;
}

}  // namespace

std::string lookAtCameraFileJson(const std::vector<LookAtCamera>& cameras) {
  json doc;
  if (cameras.size() == 1) {
    doc = lookAtJson(cameras[0]);
  } else {
    doc["cameras"] = json::array();
    for (const LookAtCamera& c : cameras) doc["cameras"].push_back(lookAtJson(c));
  }
  return jsonText(doc, 2) + "\n";
}

std::vector<CameraView> readCameraFile(const std::string& path, std::optional<std::pair<uint32_t, uint32_t>> size) {
  return parseCameraJson(readFileBytes(path), path, size);
}

}  // namespace vox
