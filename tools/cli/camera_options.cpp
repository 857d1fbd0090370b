#include "tools/cli/camera_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "libvox/core/error.h"
#include "tools/cli/comma_list.h"
#include "tools/cli/number_checks.h"

namespace voxcli {

namespace {

vox::Vec3d parseVec(const std::string& text, const std::string& option) {
  const std::string expected = "X,Y,Z (three finite numbers)";
  const std::vector<std::string> parts = splitCommaList(text, option, expected);
  if (parts.size() != 3) vox::throwUsage(option + " " + text + ": expected " + expected);
  vox::Vec3d v{};
  for (size_t i = 0; i < 3; ++i) {
    const char* p = parts[i].c_str();
    char* end = nullptr;
    v[i] = std::strtod(p, &end);
    if (end == p || *end != '\0' || !std::isfinite(v[i])) vox::throwUsage(option + " " + text + ": expected " + expected);
  }
  return v;
}

std::string vecText(const vox::Vec3d& v) {
  char text[96];
  std::snprintf(text, sizeof text, "%g,%g,%g", v[0], v[1], v[2]);
  return text;
}

}  // namespace

std::pair<uint32_t, uint32_t> parseImageSize(const std::string& text) {
  const size_t sep = text.find_first_of("x,");
  char* end = nullptr;
  const unsigned long w = std::strtoul(text.c_str(), &end, 10);
  if (sep == std::string::npos || end != text.c_str() + sep) vox::throwUsage("--size " + text + ": expected WIDTHxHEIGHT, e.g. 1920x1080");
  const unsigned long h = std::strtoul(text.c_str() + sep + 1, &end, 10);
  if (*end != '\0' || w < 1 || h < 1 || w > vox::kMaxImageSide || h > vox::kMaxImageSide)
    vox::throwUsage("--size " + text + ": expected WIDTHxHEIGHT with sides 1.." + std::to_string(vox::kMaxImageSide));
  return {uint32_t(w), uint32_t(h)};
}

void addCameraOptions(CLI::App& cmd, CameraOptions& o) {
  cmd.add_option("--eye", o.eye, "Camera position X,Y,Z (world units)");
  cmd.add_option("--target", o.target, "Point the camera looks at X,Y,Z");
  cmd.add_option("--up", o.up, "Up vector X,Y,Z (fixes the roll; not with --camera: the file's)")->default_str(vecText(vox::kLookAtUp));
  o.fovOption = cmd.add_option("--fov", o.fov, "Vertical field of view, degrees (not with --camera: the file's)")
                    ->check(FinitePositive)
                    ->capture_default_str();
  const std::string side = std::to_string(vox::kDefaultImageSide);
  cmd.add_option("--size", o.size, "Image size WIDTHxHEIGHT (default " + side + "x" + side + ", or the camera file's)");
  cmd.add_option("--camera", o.cameraFile, "Camera JSON, or a block-map metadata.json (views[] with matrices)");
  cmd.add_option("--view", o.view,
                 "A view framed on the scene: front, back, right (or side), left, top, bottom, iso; with --camera: "
                 "render only views[INDEX] (default: every view)")
      ->type_name("NAME|INDEX");
  cmd.add_option("--orbit", o.orbit, "N views around the scene at the iso elevation, framed on it (files NAME_000...)")
      ->check(CLI::Range(1u, 1000u));
}

namespace {

bool isIndex(const std::string& text) {
  return !text.empty() && text.size() < 10 && text.find_first_not_of("0123456789") == std::string::npos;
}

std::string viewNames() {
  std::string names;
  for (vox::NamedView v : vox::kNamedViews) names += std::string(names.empty() ? "" : ", ") + vox::namedViewName(v);
  return names + " (side = right)";
}

}  // namespace

bool CameraOptions::needsFraming() const { return orbit > 0 || (!view.empty() && !isIndex(view)); }

bool CameraOptions::fovGiven() const { return fovOption && fovOption->count() > 0; }

void CameraOptions::check() const {
  if (!view.empty() && !isIndex(view) && !vox::namedViewFrom(view))
    vox::throwUsage("--view " + view + ": expected one of " + viewNames() + ", or with --camera a view INDEX");
  if (!needsFraming()) {
    // A camera file is every view's whole camera: a look-at camera's "fov" and
    // "up" (absent: the documented defaults, as --camera-out writes them), a
    // metadata.json view's matrices. --fov/--up would be ignored, so refused.
    if (!cameraFile.empty() && (fovGiven() || !up.empty())) {
      const bool both = fovGiven() && !up.empty();
      const std::string option = both ? "--fov and --up" : fovGiven() ? "--fov" : "--up";
      const std::string keys = both ? "\"fov\" and \"up\"" : fovGiven() ? "\"fov\"" : "\"up\"";
      vox::throwUsage(option + (both ? " do" : " does") + " nothing with --camera " + cameraFile +
                      ": the file gives each view's field of view and up vector (a look-at camera's \"fov\" and "
                      "\"up\", a metadata.json view's matrices); drop " + option + ", or set " + keys + " in the file");
    }
    return;
  }
  const std::string what = orbit > 0 ? "--orbit" : "--view " + view;
  if (orbit > 0 && !view.empty()) vox::throwUsage("--orbit and --view " + view + " both choose the cameras; give one");
  if (!cameraFile.empty() || !eye.empty() || !target.empty() || !up.empty())
    vox::throwUsage(what + " frames the camera on the scene (eye, target and up); drop --camera/--eye/--target/--up");
  if (orbit > 1000) vox::throwUsage("--orbit " + std::to_string(orbit) + ": at most 1000 views");
}

std::string lookAtFlags(const vox::LookAtCamera& c) {
  char fov[32];
  std::snprintf(fov, sizeof fov, "%g", c.fovYDegrees);
  return "--eye " + vecText(c.eye) + " --target " + vecText(c.target) + " --up " + vecText(c.up) + " --fov " + fov +
         " --size " + std::to_string(c.width) + "x" + std::to_string(c.height);
}

std::vector<vox::CameraView> resolveCameras(const CameraOptions& o, uint32_t fallbackWidth, uint32_t fallbackHeight,
                                            const std::optional<vox::WorldBox>& framing) {
  o.check();
  std::optional<std::pair<uint32_t, uint32_t>> size;
  if (!o.size.empty()) size = parseImageSize(o.size);
  if (o.needsFraming()) {
    if (!framing) vox::throwUsage("--view NAME and --orbit need a scene to frame");
    const auto [w, h] = size.value_or(std::make_pair(fallbackWidth, fallbackHeight));
    std::vector<vox::CameraView> views;
    const uint32_t count = o.orbit > 0 ? o.orbit : 1;
    for (uint32_t i = 0; i < count; ++i) {
      vox::Vec3d toEye, up{0, 1, 0};
      std::string name;
      if (o.orbit > 0) {
        toEye = vox::orbitDirection(i, count);
        name = "orbit " + std::to_string(i) + "/" + std::to_string(count);
      } else {
        const vox::NamedView nv = *vox::namedViewFrom(o.view);
        vox::namedViewDirection(nv, toEye, up);
        name = vox::namedViewName(nv);
      }
      vox::LookAtCamera look = vox::frameBox(*framing, toEye, up, o.fov, w, h);
      look.view = name;
      vox::CameraView v;
      v.camera = look.camera();
      v.lookAt = look;
      v.label = name;
      v.index = int(i);
      views.push_back(std::move(v));
    }
    return views;
  }
  if (!o.cameraFile.empty()) {
    if (!o.eye.empty() || !o.target.empty())
      vox::throwUsage("--camera and --eye/--target describe the camera twice; give one");
    std::vector<vox::CameraView> views = vox::readCameraFile(o.cameraFile, size);
    if (!o.view.empty()) {
      const unsigned long index = std::stoul(o.view);
      if (index >= views.size())
        vox::throwUsage("--view " + o.view + ": " + o.cameraFile + " has " + std::to_string(views.size()) +
                        " view(s), 0.." + std::to_string(views.size() - 1));
      return {views[index]};
    }
    return views;
  }
  if (!o.view.empty()) vox::throwUsage("--view " + o.view + " (an index) needs --camera FILE");
  if (o.eye.empty() || o.target.empty()) vox::throwUsage("give --eye X,Y,Z and --target X,Y,Z, or --camera FILE");
  const auto [w, h] = size.value_or(std::make_pair(fallbackWidth, fallbackHeight));
  vox::CameraView v;
  const vox::Vec3d up = o.up.empty() ? vox::kLookAtUp : parseVec(o.up, "--up");
  v.camera = vox::Camera::lookAt(parseVec(o.eye, "--eye"), parseVec(o.target, "--target"), up, o.fov, w, h);
  v.lookAt = vox::LookAtCamera{parseVec(o.eye, "--eye"), parseVec(o.target, "--target"), up, o.fov, w, h, ""};
  v.label = "camera";
  return {v};
}

}  // namespace voxcli
