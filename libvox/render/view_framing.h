// Cameras without arithmetic: named views (front, back, right, left, top,
// bottom, iso) and orbits, framed on a box (render-canonical frames the
// scene's occupied voxels) so that the whole box fills the image.
//
// Conventions (world space, y up, as the block-map format's world):
//   view    eye direction from the target   up vector
//   front   +z                              +y
//   back    -z                              +y
//   right   +x   ("side" is right)          +y
//   left    -x                              +y
//   top     +y                              -z  (the back of the scene at the top of the image)
//   bottom  -y                              +z
//   iso     (1, 1, 1) / sqrt(3)             +y
// An orbit of N views circles the target at the iso elevation
// (atan(1 / sqrt(2)), 35.26 degrees): view i looks from azimuth
// 45 + 360 i / N degrees, measured from +z toward +x (view 0 is iso's azimuth).
//
// Framing: the target is the box's centre; the eye sits on the view direction
// at the smallest distance where every one of the box's 8 corners projects to
// |NDC x| <= 0.9 and |NDC y| <= 0.9 (the box touches the 0.9 frame on its
// tightest side), for the camera's vertical field of view and aspect.
//
// Thread safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "libvox/render/camera.h"

namespace vox {

/// A look-at camera as a person gives it (and as camera files hold it).
struct LookAtCamera {
  Vec3d eye{}, target{}, up = kLookAtUp;
  double fovYDegrees = kLookAtFovYDegrees;  // vertical
  uint32_t width = kDefaultImageSide, height = kDefaultImageSide;
  /// How vox chose the camera ("front", "iso", "orbit 3/8"); empty when a
  /// person gave it (--eye, a camera file without "view").
  std::string view;
  Camera camera() const { return Camera::lookAt(eye, target, up, fovYDegrees, width, height); }
  bool operator==(const LookAtCamera&) const = default;
};

enum class NamedView { Front, Back, Right, Left, Top, Bottom, Iso };

/// Every named view, in the order listed to users.
inline constexpr std::array<NamedView, 7> kNamedViews{NamedView::Front, NamedView::Back,   NamedView::Right,
                                                      NamedView::Left,  NamedView::Top,    NamedView::Bottom,
                                                      NamedView::Iso};
/// "front", "back", "right", "left", "top", "bottom", "iso".
const char* namedViewName(NamedView view);
/// The view named `name` (those names, and "side" for right), if any.
std::optional<NamedView> namedViewFrom(std::string_view name);

/// The unit direction from the target to the eye and the up vector of a view.
void namedViewDirection(NamedView view, Vec3d& toEye, Vec3d& up);
/// The direction of view `index` of an orbit of `count` views (up is +y).
Vec3d orbitDirection(uint32_t index, uint32_t count);

/// An axis-aligned world box (min <= max on every axis).
struct WorldBox {
  Vec3d min{}, max{};
};

/// The NDC limit framing keeps every corner within.
inline constexpr double kFramingNdc = 0.9;

/// The camera looking along -toEye at `box`'s centre from the distance where
/// the box's corners fill the image to kFramingNdc (see the header comment).
/// Throws vox::Error (Usage) for a bad fov or size (Camera::lookAt's checks).
LookAtCamera frameBox(const WorldBox& box, const Vec3d& toEye, const Vec3d& up, double fovYDegrees, uint32_t width,
                      uint32_t height);

/// The largest |NDC x| and |NDC y| of the box's 8 corners seen by `camera`
/// (for tests and for reporting how the box fills the image); +inf when a
/// corner is behind the eye.
std::array<double, 2> cornerNdcExtent(const Camera& camera, const WorldBox& box);

}  // namespace vox
