#include "libvox/render/view_framing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "libvox/core/error.h"

namespace vox {

namespace {

constexpr double kPi = 3.14159265358979323846;

double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

std::array<Vec3d, 8> corners(const WorldBox& b) {
  std::array<Vec3d, 8> c;
  for (int i = 0; i < 8; ++i)
    c[size_t(i)] = {(i & 1) ? b.max[0] : b.min[0], (i & 2) ? b.max[1] : b.min[1], (i & 4) ? b.max[2] : b.min[2]};
  return c;
}

}  // namespace

const char* namedViewName(NamedView view) {
  switch (view) {
    case NamedView::Front: return "front";
    case NamedView::Back: return "back";
    case NamedView::Right: return "right";
    case NamedView::Left: return "left";
    case NamedView::Top: return "top";
    case NamedView::Bottom: return "bottom";
    case NamedView::Iso: return "iso";
  }
  return "";
}

std::optional<NamedView> namedViewFrom(std::string_view name) {
  if (name == "side") return NamedView::Right;
  for (NamedView v : kNamedViews)
    if (name == namedViewName(v)) return v;
  return std::nullopt;
}

void namedViewDirection(NamedView view, Vec3d& toEye, Vec3d& up) {
  up = {0, 1, 0};
  switch (view) {
    case NamedView::Front: toEye = {0, 0, 1}; break;
    case NamedView::Back: toEye = {0, 0, -1}; break;
    case NamedView::Right: toEye = {1, 0, 0}; break;
    case NamedView::Left: toEye = {-1, 0, 0}; break;
    case NamedView::Top:
      toEye = {0, 1, 0};
      up = {0, 0, -1};
      break;
    case NamedView::Bottom:
      toEye = {0, -1, 0};
      up = {0, 0, 1};
      break;
    case NamedView::Iso: {
      const double s = 1 / std::sqrt(3.0);
      toEye = {s, s, s};
      break;
    }
  }
}

Vec3d orbitDirection(uint32_t index, uint32_t count) {
  const double elevation = std::atan(1 / std::sqrt(2.0));
  const double azimuth = (45.0 + 360.0 * double(index) / double(std::max<uint32_t>(1, count))) * kPi / 180.0;
  return {std::cos(elevation) * std::sin(azimuth), std::sin(elevation), std::cos(elevation) * std::cos(azimuth)};
}

LookAtCamera frameBox(const WorldBox& box, const Vec3d& toEye, const Vec3d& up, double fovYDegrees, uint32_t width,
                      uint32_t height) {
  LookAtCamera cam;
  cam.up = up;
  cam.fovYDegrees = fovYDegrees;
  cam.width = width;
  cam.height = height;
  for (int a = 0; a < 3; ++a) cam.target[size_t(a)] = (box.min[size_t(a)] + box.max[size_t(a)]) / 2;
  // The camera's axes, exactly as lookAtMatrix computes them (rows of the view matrix).
  Vec3d unitEye = cam.target;
  for (int a = 0; a < 3; ++a) unitEye[size_t(a)] += toEye[size_t(a)];
  const Mat4d m = lookAtMatrix(unitEye, cam.target, up);
  const Vec3d x{m[0], m[4], m[8]}, y{m[1], m[5], m[9]}, z{m[2], m[6], m[10]};
  if (!(fovYDegrees > 0 && fovYDegrees < 180))
    throwUsage("camera: the vertical field of view must be in (0, 180) degrees", Setting::FieldOfView);
  const double f = 1.0 / std::tan(fovYDegrees * kPi / 360.0), aspect = double(width) / double(height);
  // A corner q (relative to the target) at eye distance D has depth D - q.z and
  // NDC (q.x f / aspect, q.y f) / depth: the smallest D keeping both within the
  // limit. The limit is shaded by 1e-9 so that rounding in the camera actually
  // built cannot push a corner past it.
  const double limit = kFramingNdc * (1 - 1e-9);
  double distance = 0, diagonal = 0;
  for (int a = 0; a < 3; ++a) diagonal = std::max(diagonal, box.max[size_t(a)] - box.min[size_t(a)]);
  for (const Vec3d& c : corners(box)) {
    const Vec3d q{c[0] - cam.target[0], c[1] - cam.target[1], c[2] - cam.target[2]};
    const double need = std::max(std::fabs(dot(q, x)) * f / (aspect * limit), std::fabs(dot(q, y)) * f / limit);
    distance = std::max(distance, dot(q, z) + std::max(need, 1e-6 * diagonal));
  }
  if (!(distance > 0)) distance = 1;  // an empty box: any distance frames it
  for (int a = 0; a < 3; ++a) cam.eye[size_t(a)] = cam.target[size_t(a)] + distance * toEye[size_t(a)];
  return cam;
}

std::array<double, 2> cornerNdcExtent(const Camera& camera, const WorldBox& box) {
  std::array<double, 2> extent{0, 0};
  const Mat4d& v = camera.view;
  const Mat4d& p = camera.projection;
  for (const Vec3d& c : corners(box)) {
    double e[4];
    for (int r = 0; r < 4; ++r) e[r] = v[size_t(r)] * c[0] + v[size_t(4 + r)] * c[1] + v[size_t(8 + r)] * c[2] + v[size_t(12 + r)];
    double clip[4];
    for (int r = 0; r < 4; ++r)
      clip[r] = p[size_t(r)] * e[0] + p[size_t(4 + r)] * e[1] + p[size_t(8 + r)] * e[2] + p[size_t(12 + r)] * e[3];
    if (!(clip[3] > 0)) return {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    extent[0] = std::max(extent[0], std::fabs(clip[0] / clip[3]));
    extent[1] = std::max(extent[1], std::fabs(clip[1] / clip[3]));
  }
  return extent;
}

}  // namespace vox
