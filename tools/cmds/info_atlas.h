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

namespace voxcli {

/// Describes the atlas `image` read from `path` on stdout (text or JSON).
/// `pixel` is "" or "x,y"; `scene` is "" or the scene / page file for class
/// names and votes (default: the scene the atlas names, when it exists).
int infoAtlas(const std::string& path, const vox::Image& image, const std::string& pixel, const std::string& scene,
              bool json);

/// The class table of a scene (.vdb) or page file (.vpk), or nullopt when the
/// file does not exist. Throws vox::Error when it exists but cannot be read.
std::optional<vox::ClassTable> classTableOf(const std::string& path);

/// The summary bytes explained in words, one short line each: "Stone (class
/// 3)", "confidence 78% (200/255)", "observations 57 (total votes 10..11)",
/// "margin 4.71% (12/255) of the votes" (one line for an empty texel).
std::vector<std::string> explainSummary(int cls, int conf, int obs, int mrg, const vox::ClassTable* classes);

}  // namespace voxcli
