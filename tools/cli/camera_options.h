// Camera options shared by render-canonical and verify-bijection --canonical:
// --eye/--target/--up/--fov/--size, --camera FILE [--view N], or a camera vox
// frames on the scene: --view front|back|right|left|top|bottom|iso (side =
// right) or --orbit N (libvox/render/view_framing.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "formats/core/camera_json.h"

namespace CLI {
class App;
class Option;
}

namespace voxcli {

struct CameraOptions {
  std::string eye, target;
  std::string up;          // "X,Y,Z"; empty: vox::kLookAtUp
  double fov = vox::kLookAtFovYDegrees;
  std::string size;        // "WIDTHxHEIGHT"
  std::string cameraFile;  // camera JSON or a block-map metadata.json
  std::string view;        // with --camera: one view's INDEX; else a named view
  uint32_t orbit = 0;      // --orbit N: N framed views around the scene
  const CLI::Option* fovOption = nullptr;  // to tell --fov given from its default

  bool given() const { return !eye.empty() || !target.empty() || !cameraFile.empty() || needsFraming(); }
  /// --view NAME or --orbit: the cameras depend on the scene's occupied box.
  bool needsFraming() const;
  /// --fov was given (not only its default).
  bool fovGiven() const;
  /// Refuses contradictory options, and options the cameras would not use
  /// (--fov/--up with --camera FILE), before anything is read. Throws vox::Error (Usage).
  void check() const;
};

/// Adds the options to `cmd`.
void addCameraOptions(CLI::App& cmd, CameraOptions& options);

/// The cameras the options describe; `fallbackSize` is used when neither
/// --size nor the file gives one; `framing` is the world box named views and
/// orbits frame (required when needsFraming()). Throws vox::Error (Usage / BadInput).
std::vector<vox::CameraView> resolveCameras(const CameraOptions& options, uint32_t fallbackWidth,
                                            uint32_t fallbackHeight,
                                            const std::optional<vox::WorldBox>& framing = std::nullopt);

/// A camera as flags a person can paste: "--eye X,Y,Z --target X,Y,Z --up X,Y,Z --fov F --size WxH".
std::string lookAtFlags(const vox::LookAtCamera& camera);

/// Parses "WxH" (also "W,H"); throws vox::Error (Usage).
std::pair<uint32_t, uint32_t> parseImageSize(const std::string& text);

}  // namespace voxcli
