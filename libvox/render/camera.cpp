#include "libvox/render/camera.h"

#include <cmath>

#include "libvox/core/error.h"

namespace vox {

namespace {

Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double length(const Vec3d& a) { return std::sqrt(dot(a, a)); }

}  // namespace

Mat4d lookAtMatrix(const Vec3d& eye, const Vec3d& center, const Vec3d& up) {
  // gl-matrix's lookAt, which the block-map format's cameras come from:
  // z = normalize(eye - center), x = normalize(up x z), y = z x x.
  Vec3d z = sub(eye, center);
  const double zl = length(z);
  if (!(zl > 0) || !std::isfinite(zl))
    throwUsage("camera: the eye and the target must be distinct finite points", Setting::CameraPose);
  for (double& c : z) c /= zl;
  Vec3d x = cross(up, z);
  const double xl = length(x);
  if (!(xl > 1e-12 * std::max(1.0, length(up))) || !std::isfinite(xl))
    throwUsage("camera: the up vector is parallel to the view direction (or zero); the roll is undefined",
               Setting::CameraUp);
  for (double& c : x) c /= xl;
  const Vec3d y = cross(z, x);
  return {x[0], y[0], z[0], 0,  //
          x[1], y[1], z[1], 0,  //
          x[2], y[2], z[2], 0,  //
          -dot(x, eye), -dot(y, eye), -dot(z, eye), 1};
}

Mat4d perspectiveMatrix(double fovY, double aspect, double near, double far) {
  const double f = 1.0 / std::tan(fovY / 2);
  const double nf = 1 / (near - far);
  Mat4d m{};
  m[0] = f / aspect;
  m[5] = f;
  m[10] = (far + near) * nf;
  m[11] = -1;
  m[14] = 2 * far * near * nf;
  return m;
}

Mat4d inverse(const Mat4d& m) {
  // Cofactor expansion (as gl-matrix's invert), in double.
  const double a00 = m[0], a01 = m[1], a02 = m[2], a03 = m[3];
  const double a10 = m[4], a11 = m[5], a12 = m[6], a13 = m[7];
  const double a20 = m[8], a21 = m[9], a22 = m[10], a23 = m[11];
  const double a30 = m[12], a31 = m[13], a32 = m[14], a33 = m[15];
  const double b00 = a00 * a11 - a01 * a10, b01 = a00 * a12 - a02 * a10, b02 = a00 * a13 - a03 * a10;
  const double b03 = a01 * a12 - a02 * a11, b04 = a01 * a13 - a03 * a11, b05 = a02 * a13 - a03 * a12;
  const double b06 = a20 * a31 - a21 * a30, b07 = a20 * a32 - a22 * a30, b08 = a20 * a33 - a23 * a30;
  const double b09 = a21 * a32 - a22 * a31, b10 = a21 * a33 - a23 * a31, b11 = a22 * a33 - a23 * a32;
  const double det = b00 * b11 - b01 * b10 + b02 * b09 + b03 * b08 - b04 * b07 + b05 * b06;
  if (!(std::fabs(det) > 0) || !std::isfinite(det)) throwBadInput("camera: the view matrix is singular");
  const double d = 1.0 / det;
  return {(a11 * b11 - a12 * b10 + a13 * b09) * d, (a02 * b10 - a01 * b11 - a03 * b09) * d,
          (a31 * b05 - a32 * b04 + a33 * b03) * d, (a22 * b04 - a21 * b05 - a23 * b03) * d,
          (a12 * b08 - a10 * b11 - a13 * b07) * d, (a00 * b11 - a02 * b08 + a03 * b07) * d,
          (a32 * b02 - a30 * b05 - a33 * b01) * d, (a20 * b05 - a22 * b02 + a23 * b01) * d,
          (a10 * b10 - a11 * b08 + a13 * b06) * d, (a01 * b08 - a00 * b10 - a03 * b06) * d,
          (a30 * b04 - a31 * b02 + a33 * b00) * d, (a21 * b02 - a20 * b04 - a23 * b00) * d,
          (a11 * b07 - a10 * b09 - a12 * b06) * d, (a00 * b09 - a01 * b07 + a02 * b06) * d,
          (a31 * b01 - a30 * b03 - a32 * b00) * d, (a20 * b03 - a21 * b01 + a22 * b00) * d};
}

Camera Camera::make(const Mat4d& view, const Mat4d& projection, uint32_t width, uint32_t height,
                    const std::string& what) {
  for (int i = 0; i < 16; ++i) {
    if (!std::isfinite(view[size_t(i)]))
      throwBadInput(what + ": viewMatrix[" + std::to_string(i) + "] is not a finite number");
    if (!std::isfinite(projection[size_t(i)]))
      throwBadInput(what + ": projectionMatrix[" + std::to_string(i) + "] is not a finite number");
  }
  if (projection[11] != -1 || projection[15] != 0 || projection[0] == 0 || projection[5] == 0)
    throwBadInput(what +
                  ": projectionMatrix is not a perspective projection (expected m[11] = -1, m[15] = 0 and "
                  "non-zero m[0], m[5], column-major as the block-map format's cameras)");
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    throwBadInput(what + ": image size " + std::to_string(width) + " x " + std::to_string(height) +
                  " is outside 1.." + std::to_string(kMaxImageSide));
  Camera c;
  c.view = view;
  c.projection = projection;
  c.width = width;
  c.height = height;
  try {
    c.cameraToWorld = inverse(view);
  } catch (const Error&) {
    throwBadInput(what + ": the view matrix is singular");
  }
  c.eye = {c.cameraToWorld[12], c.cameraToWorld[13], c.cameraToWorld[14]};
  for (double e : c.eye)
    if (!std::isfinite(e) || std::fabs(e) > kMaxCameraCoordinate)
      throwBadInput(what + ": the eye position is not finite or beyond +-1e15 world units");
  return c;
}

std::string withoutCameraLead(const std::string& message) {
  static const std::string kLead = "camera: ";
  return message.compare(0, kLead.size(), kLead) == 0 ? message.substr(kLead.size()) : message;
}

Camera Camera::lookAt(const Vec3d& eye, const Vec3d& target, const Vec3d& up, double fovYDegrees,
                      uint32_t width, uint32_t height) {
  for (const Vec3d* v : {&eye, &target, &up})
    for (double x : *v)
      if (!std::isfinite(x) || std::fabs(x) > kMaxCameraCoordinate)
        throwUsage("camera: the eye, target and up vector must be finite numbers within +-1e15 world units",
                   Setting::CameraPose);
  if (!(fovYDegrees > 0 && fovYDegrees < 180))
    throwUsage("camera: the vertical field of view must be in (0, 180) degrees", Setting::FieldOfView);
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    throwUsage("camera: the image size must be 1.." + std::to_string(kMaxImageSide) + " on each side",
               Setting::ImageSize);
  const double pi = 3.14159265358979323846;
  return make(lookAtMatrix(eye, target, up),
              perspectiveMatrix(fovYDegrees * pi / 180.0, double(width) / double(height), kLookAtNear, kLookAtFar),
              width, height, "camera");
}

void Camera::pixelRay(uint32_t x, uint32_t y, Vec3d& origin, Vec3d& direction) const {
  const double ndcX = 2.0 * (double(x) + 0.5) / double(width) - 1.0;
  const double ndcY = 1.0 - 2.0 * (double(y) + 0.5) / double(height);
  const double cx = (ndcX + projection[8]) / projection[0];
  const double cy = (ndcY + projection[9]) / projection[5];
  const double cz = -1.0;
  const Mat4d& m = cameraToWorld;
  Vec3d d = {m[0] * cx + m[4] * cy + m[8] * cz, m[1] * cx + m[5] * cy + m[9] * cz, m[2] * cx + m[6] * cy + m[10] * cz};
  const double l = length(d);
  for (double& c : d) c /= l;
  origin = eye;
  direction = d;
}

}  // namespace vox
