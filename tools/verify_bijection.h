// Shared between the launcher's and the module's verify-bijection.
#pragma once

#include <string>

#include "tools/cli.h"

namespace voxcli {

struct VerifyBijectionOptions {
  std::string dims;
  uint32_t res = 0;
  uint32_t tilesPerRow = 0;
  uint32_t maxSide = 16384;
  std::string format;
  std::string atlas, scene;
  bool json = false;
  CommonOptions common;
};

/// True when the command line needs the scene module (--atlas, --scene, --canonical).
bool needsSceneModule(int argc, char** argv);

/// `verify-bijection --atlas FILE --scene S` (tools/verify_atlas.cpp, module only).
int runAtlasCheck(const VerifyBijectionOptions& options);

}  // namespace voxcli
