// `vox info` for render-canonical images: what the image is and, with
// --pixel x,y, the voxel under that pixel (picking), and with --scene its class,
// summary bytes and votes (tools/cmds/cmd_info.cpp calls this).
#pragma once

#include <optional>
#include <string>

#include "formats/image/image.h"
#include "tools/cmds/info_pixel.h"

namespace voxcli {

/// Describes `image` (read from `path`, carrying a "vox:canonical" entry) on
/// stdout, text or JSON. `pixel` is the pixel to pick, if any (outside the
/// image: vox::Error, Usage); `scene` is "" or the scene / page file to look
/// the voxel up in (with `pixel` only). Returns the exit code.
int infoCanonical(const std::string& path, const vox::Image& image, const std::optional<PixelXY>& pixel,
                  const std::string& scene, bool json);

}  // namespace voxcli
