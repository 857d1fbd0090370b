// Pinhole cameras given as intrinsics + pose (the OpenCV convention most
// depth sensors and reconstruction tools use), turned into voxbake cameras
// (camera.h) with the same ray through every pixel centre.
//
// OpenCV: camera x right, y down, z forward; pixel (x, y)'s centre is at image
// coordinates (x, y); a camera point (X, Y, Z) projects to
// (fx X / Z + cx, fy Y / Z + cy). pose = camera-to-world, column-major 4x4.
// camera.h: pixel (x, y)'s centre is NDC (2 (x + 0.5) / W - 1, 1 - 2 (y + 0.5) / H)
// and its camera-space direction ((ndc_x + P[8]) / P[0], (ndc_y + P[9]) / P[5], -1).
// Equating the two directions for every pixel gives
//   P[0] = 2 fx / W, P[5] = 2 fy / H, P[8] = (W - 1 - 2 cx) / W, P[9] = (2 cy - H + 1) / H,
// and view = diag(1, -1, -1, 1) * inverse(pose) (the OpenGL camera looks down -z, y up).
#pragma once

#include <cstdint>
#include <string>

#include "libvox/render/camera.h"

namespace vox {

struct Intrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
};

/// The camera; throws vox::Error (BadInput) naming `what` when fx or fy is
/// not > 0, a value is not finite, or the pose is singular.
Camera intrinsicsCamera(const Intrinsics& k, const Mat4d& pose, uint32_t width, uint32_t height, const std::string& what);

}  // namespace vox
