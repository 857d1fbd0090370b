// Names of enum option values that several commands share, in one place
// (tools/cli/enum_option.h parses them; reports print them back with nameOf).
#pragma once

#include "libvox/scene/mip.h"
#include "tools/bake/voxelize_mesh.h"
#include "tools/cli/enum_option.h"

namespace voxcli {

/// --occupancy of `vox mip` and `vox pack-chunks --mips`: any | majority.
inline const EnumNames<vox::MipOccupancy>& mipOccupancyNames() {
  static const EnumNames<vox::MipOccupancy> names{
      {vox::mipOccupancyName(vox::MipOccupancy::Any), vox::MipOccupancy::Any},
      {vox::mipOccupancyName(vox::MipOccupancy::Majority), vox::MipOccupancy::Majority}};
  return names;
}

}  // namespace voxcli
