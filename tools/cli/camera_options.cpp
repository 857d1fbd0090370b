#include "tools/cli/camera_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "libvox/core/error.h"
#include "tools/cli/number_checks.h"

namespace voxcli {

namespace {

vox::Vec3d parseVec(const std::string& text, const std::string& option) {
  vox::Vec3d v{};
  const char* p = text.c_str();
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    v[size_t(i)] = std::strtod(p, &end);
    if (end == p || !std::isfinite(v[size_t(i)])) vox::throwUsage(option + " " + text + ": expected X,Y,Z (three finite numbers)");
    p = end;
    if (i < 2) {
      if (*p != ',') vox::throwUsage(option + " " + text + ": expected X,Y,Z (three finite numbers)");
      ++p;
    }
  }
  if (*p != '\0') vox::throwUsage(option + " " + text + ": expected X,Y,Z (three finite numbers)");
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
  cmd.add_option("--up", o.up, "Up vector X,Y,Z (fixes the roll)")->default_str(vecText(vox::kLookAtUp));
  cmd.add_option("--fov", o.fov, "Vertical field of view, degrees")->check(FinitePositive)->capture_default_str();
  const std::string side = std::to_string(vox::kDefaultImageSide);
  cmd.add_option("--size", o.size, "Image size WIDTHxHEIGHT (default " + side + "x" + side + ", or the camera file's)");
  cmd.add_option("--camera", o.cameraFile, "Camera JSON, or a block-map metadata.json (views[] with matrices)");
  cmd.add_option("--view", o.view, "With --camera: render only views[INDEX] (default: every view)");
}

std::vector<vox::CameraView> resolveCameras(const CameraOptions& o, uint32_t fallbackWidth, uint32_t fallbackHeight) {
  std::optional<std::pair<uint32_t, uint32_t>> size;
  if (!o.size.empty()) size = parseImageSize(o.size);
  if (!o.cameraFile.empty()) {
    if (!o.eye.empty() || !o.target.empty())
      vox::throwUsage("--camera and --eye/--target describe the camera twice; give one");
    std::vector<vox::CameraView> views = vox::readCameraFile(o.cameraFile, size);
    if (o.view >= 0) {
      if (size_t(o.view) >= views.size())
        vox::throwUsage("--view " + std::to_string(o.view) + ": " + o.cameraFile + " has " +
                        std::to_string(views.size()) + " view(s), 0.." + std::to_string(views.size() - 1));
      return {views[size_t(o.view)]};
    }
    return views;
  }
  if (o.view >= 0) vox::throwUsage("--view needs --camera FILE");
  if (o.eye.empty() || o.target.empty()) vox::throwUsage("give --eye X,Y,Z and --target X,Y,Z, or --camera FILE");
  const auto [w, h] = size.value_or(std::make_pair(fallbackWidth, fallbackHeight));
  vox::CameraView v;
  const vox::Vec3d up = o.up.empty() ? vox::kLookAtUp : parseVec(o.up, "--up");
  v.camera = vox::Camera::lookAt(parseVec(o.eye, "--eye"), parseVec(o.target, "--target"), up, o.fov, w, h);
  v.label = "camera";
  return {v};
}

}  // namespace voxcli
