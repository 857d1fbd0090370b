// `vox voxelize`: its options, and the mesh bake that needs no OpenVDB.
//
// The command is registered twice with the same options: in the full command
// module (tools/cmds/cmd_voxelize.cpp, vox-cmds.so, every input kind) and in the
// light bake module (tools/bake/bake_main.cpp, vox-bake.so, which does not link
// OpenVDB). The launcher tries the light module first for `vox voxelize`; it
// answers kDeferToFullModule, before doing anything, when the command line needs
// the full one (non-mesh inputs, --method sdf, --check).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "libvox/mesh/mesh.h"
#include "libvox/core/scene_header.h"
#include "libvox/mesh/voxelize.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"

namespace voxcli {

struct VoxelizeOptions {
  std::vector<std::string> inputs;
  std::string output;
  uint32_t resolution = 0;  // 0 = the input's default (demo: 256)
  std::string gridSize = "64,48,64";
  double voxelSize = 0;
  std::string gridName;
  std::optional<double> threshold;
  std::string fill = "surface";
  std::string method = "exact";
  std::string bounds;
  uint32_t pad = 0;
  std::string classes;
  bool dropInvalid = false;
  bool ignoreMissingMaterials = false;
  bool check = false;
  CommonOptions common;
};

/// True when `s` ends with `suffix` (lower case), ignoring the case of `s`.
bool endsWithLower(const std::string& s, const std::string& suffix);

/// Adds the `voxelize` subcommand and every option to `root`, filling `opts`.
CLI::App* addVoxelizeCommand(CLI::App& root, VoxelizeOptions& opts);

/// Checks what holds for every input kind (--res vs --voxel-size, *.vdb output,
/// input combinations); throws vox::Error (Usage).
void checkVoxelizeOptions(const VoxelizeOptions& o);
bool allInputsAreMeshes(const VoxelizeOptions& o);
/// True when the light module can run this command line: meshes only, the
/// exact method, no --check.
bool isLightBake(const VoxelizeOptions& o);

/// The meshes read, classes assigned and the scene placed: the "parse" and
/// "prepare" phases of a mesh bake.
struct PreparedMeshes {
  vox::Mesh mesh;
  std::vector<uint8_t> triangleClass;
  vox::SceneHeader header;
  std::vector<std::string> warnings;
  uint64_t bytesRead = 0;
};
PreparedMeshes prepareMeshes(const VoxelizeOptions& o, Run& run);

/// Voxelizer settings from the options (--fill, --threads), reporting progress to `bar`.
vox::VoxelizeSettings voxelizeSettings(const VoxelizeOptions& o, const Run& run, ProgressBar& bar);

/// The counts and the closing message of a mesh bake, then run.finish().
int finishMeshBake(const VoxelizeOptions& o, Run& run, const PreparedMeshes& p, uint64_t occupied, uint64_t surface,
                   size_t classesPresent);

/// The mesh bake without OpenVDB: prepare, voxelize into blocks, write the
/// .vdb directly (formats/scene/scene_vdb_direct.h), report. Returns the exit code.
int runMeshesDirect(const VoxelizeOptions& o, Run& run, const std::string& outputTemp);

/// The light module's registration of `voxelize`.
Command registerVoxelizeLight(CLI::App& root);

/// vox's root description (both modules print it in --help).
extern const char* const kRootDescription;

}  // namespace voxcli
