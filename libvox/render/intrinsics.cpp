#include "libvox/render/intrinsics.h"

#include <cmath>

#include "libvox/core/error.h"

namespace vox {

Camera intrinsicsCamera(const Intrinsics& k, const Mat4d& pose, uint32_t width, uint32_t height, const std::string& what) {
  if (!(std::isfinite(k.fx) && k.fx > 0 && std::isfinite(k.fy) && k.fy > 0 && std::isfinite(k.cx) && std::isfinite(k.cy)))
    throwBadInput(what + ": intrinsics: fx and fy must be > 0, cx and cy finite");
  Mat4d worldToCv;
  try {
    worldToCv = inverse(pose);
  } catch (const Error&) {
    throwBadInput(what + ": the pose is singular (it must be an invertible camera-to-world matrix)");
  }
  // OpenCV axes (y down, z forward) to OpenGL's (y up, z backward): negate rows 1 and 2.
  Mat4d view = worldToCv;
  for (size_t col = 0; col < 4; ++col) {
    view[col * 4 + 1] = -view[col * 4 + 1];
    view[col * 4 + 2] = -view[col * 4 + 2];
  }
  const double W = width, H = height;
  Mat4d proj{};
  proj[0] = 2 * k.fx / W;
  proj[5] = 2 * k.fy / H;
  proj[8] = (W - 1 - 2 * k.cx) / W;
  proj[9] = (2 * k.cy - H + 1) / H;
  proj[10] = (kLookAtFar + kLookAtNear) / (kLookAtNear - kLookAtFar);
  proj[11] = -1;
  proj[14] = 2 * kLookAtFar * kLookAtNear / (kLookAtNear - kLookAtFar);
  return Camera::make(view, proj, width, height, what);
}

}  // namespace vox
