// `vox info` for atlases and occupancy bitmaps (build-atlas outputs, the
// touched bitmap of render-canonical): the layout, what each channel or bit
// means, what the texels hold (per class for a summary atlas, the class of a
// votes layer), and with --pixel x,y one texel decoded to its voxel.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "formats/image/image.h"
#include "libvox/core/classes.h"
#include "tools/cmds/info_pixel.h"

namespace voxcli {

/// Describes the atlas `image` read from `path` on stdout (text or JSON).
/// `pixel` is the texel asked for, if any (outside the atlas: vox::Error,
/// Usage); `scene` is "" or the scene / page file for class
/// names and votes (default: the scene the atlas names, when it exists and
/// has the atlas's dims). Throws vox::Error (BadInput) when `scene` is given
/// and its dims are not the atlas's: it is not the scene the atlas was built
/// from.
int infoAtlas(const std::string& path, const vox::Image& image, const std::optional<PixelXY>& pixel,
              const std::string& scene, bool json);

/// What `vox info` takes from a scene (.vdb, level 0) or page file (.vpk):
/// its class table, and its grid's dims, which must be an atlas's dims for the
/// scene to be the one the atlas was built from.
struct SceneFacts {
  vox::ClassTable classes;
  vox::Dims dims;
};
/// The facts of the scene or page file at `path`, or nullopt when there is no
/// regular file there. Throws vox::Error when it exists but cannot be read.
std::optional<SceneFacts> sceneFactsOf(const std::string& path);

/// The summary bytes explained in words, one short line each: "Stone (class
/// 3)", "confidence 78% (200/255)", "observations 57 (total votes 10..11)",
/// "margin 4.71% (12/255) of the votes" (one line for an empty texel).
std::vector<std::string> explainSummary(int cls, int conf, int obs, int mrg, const vox::ClassTable* classes);

}  // namespace voxcli
