// Camera files for render-canonical and verify-bijection --canonical.
//
// Three JSON shapes are accepted (README "Cameras"):
//   * the block-map format's metadata.json: {"imageSize": {"width", "height"},
//       "views": [{"index", "id", "viewMatrix": [16], "projectionMatrix": [16], ...}]}
//     with column-major matrices; every other field is ignored.
//   * one look-at camera: {"eye": [x,y,z], "target": [x,y,z], "up": [0,1,0],
//       "fov": 60, "size": [width, height], "view": "front"}   (up, fov, size
//     optional: the defaults are camera.h's kLookAtUp, kLookAtFovYDegrees,
//     kDefaultImageSide; "view" names how vox chose the camera, as
//     render-canonical --camera-out writes it, and is optional)
//   * several: {"cameras": [ look-at camera, ... ]}
// Errors are vox::Error (BadInput) naming the file and the element
// ("views[2].viewMatrix[5]").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "libvox/render/camera.h"
#include "libvox/render/view_framing.h"

namespace vox {

struct CameraView {
  Camera camera;
  std::string label;  // "view 3 (view_004)" or "camera 0"
  std::string source;  // "FILE: cameras[2]" when read from a file (its problems are bad input), else ""
  int index = 0;      // position in the file
  std::optional<LookAtCamera> lookAt;  // when the camera was given as a look-at camera
};

/// Reads every camera of `path`. `size` (width, height) overrides the file's
/// image size when given (the projection is kept, so the aspect may change).
std::vector<CameraView> readCameraFile(const std::string& path, std::optional<std::pair<uint32_t, uint32_t>> size);

/// The camera-file text of look-at cameras: one camera object for one camera,
/// {"cameras": [...]} for several; every number at full precision (reading it
/// back gives the same doubles), keys sorted, two-space indentation, a final newline.
std::string lookAtCameraFileJson(const std::vector<LookAtCamera>& cameras);

/// Parses the same from text (tests); `name` is used in messages.
std::vector<CameraView> parseCameraJson(const std::string& text, const std::string& name,
                                        std::optional<std::pair<uint32_t, uint32_t>> size);

}  // namespace vox
