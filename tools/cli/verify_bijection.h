// Shared between the launcher's and the module's verify-bijection.
#pragma once

#include <string>

#include "libvox/render/render.h"
#include "libvox/core/atlas_mapping.h"
#include "tools/cli/camera_options.h"
#include "tools/cli/cli.h"

namespace voxcli {

struct VerifyBijectionOptions {
  std::string dims;
  uint32_t res = 0;
  uint32_t tilesPerRow = 0;
  uint32_t maxSide = vox::kDefaultAtlasMaxSide;
  std::string format;
  std::string atlas, scene;
  std::string canonical;       // --canonical IMG: a render-canonical image to check against --scene
  CameraOptions camera;        // with --canonical: the camera to re-cast (default: the image's own)
  double checkBudget = vox::kDefaultCheckBudget;  // ray-voxel tests the brute force may spend
  bool json = false;
  CommonOptions common;
};

/// True when the command line needs the scene module (--atlas, --scene, --canonical).
bool needsSceneModule(int argc, char** argv);

/// `verify-bijection --atlas FILE --scene S` (tools/cmds/verify_atlas.cpp, module only).
int runAtlasCheck(const VerifyBijectionOptions& options);
/// `verify-bijection --canonical IMG --scene S [camera]` (tools/cmds/verify_canonical.cpp, module only).
int runCanonicalCheck(const VerifyBijectionOptions& options);

}  // namespace voxcli
