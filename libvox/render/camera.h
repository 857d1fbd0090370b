// Pinhole cameras for render-canonical, in the block-map format's conventions
// (its map.json / metadata.json cameras: column-major view/projection
// matrices, OpenGL clip z).
//
// Matrices are 4x4, column-major as flat arrays of 16 (element (row r, col c)
// is m[c * 4 + r]), OpenGL clip space (z in [-1, 1]), as the block-map
// format's camera.ts and metadata.json have them:
//   lookAtMatrix: world -> camera; the camera looks down its -z axis, +y is up.
//   perspectiveMatrix: f = 1 / tan(fovY / 2); m[0] = f / aspect, m[5] = f,
//     m[10] = (far + near) / (near - far), m[11] = -1, m[14] = 2 far near / (near - far).
//
// Image conventions: pixel (x, y) with row 0 at the top; one ray per pixel
// centre: NDC x = 2 (x + 0.5) / W - 1, NDC y = 1 - 2 (y + 0.5) / H.
// The ray of a pixel leaves the eye through the point the projection maps to
// that NDC position at z_camera = -1:
//   dir_camera = ((ndc_x + P[8]) / P[0], (ndc_y + P[9]) / P[5], -1)
// (P[8], P[9] are the off-centre terms, 0 for the block-map format's matrices), then
//   dir_world = inverse(view) applied to (dir_camera, 0)
// (pixelRay normalises it to length 1; the renderer's PixelRays, render.h,
// uses it as is and measures depth with its length). Rays start at the eye: near and far
// are not used (a voxel between the eye and the near plane is still hit).
//
// All arithmetic is double; the same camera gives bit-identical rays on every
// machine and thread count.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "libvox/core/scene_header.h"

namespace vox {

using Vec3d = std::array<double, 3>;
using Mat4d = std::array<double, 16>;  // column-major

/// A look-at camera's defaults, wherever it is described (options, camera files).
inline constexpr Vec3d kLookAtUp{0, 1, 0};
inline constexpr double kLookAtFovYDegrees = 60;  // vertical
inline constexpr uint32_t kDefaultImageSide = 512;  // when nothing gives the image size
/// The block-map format's near and far planes; rays ignore them.
inline constexpr double kLookAtNear = 0.1, kLookAtFar = 500;
/// Cameras farther than this from the world origin, on any axis, are refused:
/// beyond it doubles no longer resolve a unit, so no ray could be exact.
inline constexpr double kMaxCameraCoordinate = kMaxWorldCoordinate;
/// The largest image side a camera renders.
inline constexpr uint32_t kMaxImageSide = 65536;

/// World -> camera, gl-matrix's lookAt (the block-map format's). Throws
/// vox::Error (Usage, Setting::CameraPose / CameraUp) when eye == center or up
/// is parallel to the view direction (the roll is undefined).
Mat4d lookAtMatrix(const Vec3d& eye, const Vec3d& center, const Vec3d& up);
/// gl-matrix's perspective (the block-map format's createPerspective); fovY in radians.
Mat4d perspectiveMatrix(double fovYRadians, double aspect, double near, double far);
/// General 4x4 inverse; throws vox::Error (BadInput) when singular.
Mat4d inverse(const Mat4d& m);

struct Camera {
  Mat4d view{};        // world -> camera
  Mat4d projection{};  // camera -> clip (perspective)
  uint32_t width = 0, height = 0;
  // Derived by make():
  Mat4d cameraToWorld{};
  Vec3d eye{};

  /// Checks and derives: the projection must be a perspective one (P[11] = -1,
  /// P[15] = 0, P[0], P[5] != 0), the view invertible, every entry finite,
  /// 1 <= width, height <= kMaxImageSide. Throws vox::Error (BadInput) naming `what`.
  static Camera make(const Mat4d& view, const Mat4d& projection, uint32_t width, uint32_t height,
                     const std::string& what);
  /// A camera at `eye` looking at `target`: fov is vertical, in degrees; aspect =
  /// width / height; near and far kLookAtNear and kLookAtFar (they do not affect
  /// rays). Throws vox::Error (Usage) with the Setting to change.
  static Camera lookAt(const Vec3d& eye, const Vec3d& target, const Vec3d& up, double fovYDegrees,
                       uint32_t width, uint32_t height);

  /// World-space ray of pixel (x, y): origin = eye, direction of length 1.
  void pixelRay(uint32_t x, uint32_t y, Vec3d& origin, Vec3d& direction) const;
};

/// A camera error's text without its leading "camera: ", for callers that
/// name the camera themselves ("cams.json: cameras[1]: the vertical field...").
std::string withoutCameraLead(const std::string& message);

}  // namespace vox
