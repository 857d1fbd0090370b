// The launcher hands every --atlas/--scene command line to the module before
// parsing (tools/cli/main.cpp), so this is only reached if that routing breaks.
#include "libvox/core/error.h"
#include "tools/cli/verify_bijection.h"

namespace voxcli {
int runAtlasCheck(const VerifyBijectionOptions&) {
  throw vox::Error(vox::ErrorKind::Internal, "atlas checks run in the command module; the launcher did not route it");
}
int runCanonicalCheck(const VerifyBijectionOptions&) {
  throw vox::Error(vox::ErrorKind::Internal, "canonical checks run in the command module; the launcher did not route it");
}
}  // namespace voxcli
