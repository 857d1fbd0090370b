// Camera options shared by render-canonical and verify-bijection --canonical:
// --eye/--target/--up/--fov/--size, or --camera FILE [--view N].
#pragma once

#include <string>
#include <vector>

#include "formats/core/camera_json.h"

namespace CLI {
class App;
}

namespace voxcli {

struct CameraOptions {
  std::string eye, target;
  std::string up;          // "X,Y,Z"; empty: vox::kLookAtUp
  double fov = vox::kLookAtFovYDegrees;
  std::string size;        // "WIDTHxHEIGHT"
  std::string cameraFile;  // camera JSON or a block-map metadata.json
  int view = -1;           // with --camera: one view (default: all)

  bool given() const { return !eye.empty() || !target.empty() || !cameraFile.empty(); }
};

/// Adds the options to `cmd`.
void addCameraOptions(CLI::App& cmd, CameraOptions& options);

/// The cameras the options describe; `fallbackSize` is used when neither
/// --size nor the file gives one. Throws vox::Error (Usage / BadInput).
std::vector<vox::CameraView> resolveCameras(const CameraOptions& options, uint32_t fallbackWidth,
                                            uint32_t fallbackHeight);

/// Parses "WxH" (also "W,H"); throws vox::Error (Usage).
std::pair<uint32_t, uint32_t> parseImageSize(const std::string& text);

}  // namespace voxcli
