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

#include "libvox/core/city_extent.h"
#include "libvox/mesh/mesh.h"
#include "libvox/core/scene_header.h"
#include "libvox/mesh/voxelize.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/enum_option.h"

namespace vox {
class DeferredTextures;  // formats/mesh/deferred_textures.h
}  // namespace vox

namespace voxcli {

/// How meshes become voxels.
enum class VoxelizeMethod {
  Exact,  // the exact voxelizer (libvox/mesh/voxelize.h)
  Sdf,    // OpenVDB's meshToVolume, for comparison (libvox/scene/voxelize_sdf.h)
};

/// The options of `vox voxelize`, with their defaults: the one place they are set.
struct VoxelizeOptions {
  static constexpr uint32_t kDefaultResolution = 256;

  std::vector<std::string> inputs;
  std::string output;
  uint32_t resolution = 0;  // voxels on the longest side; 0 = not given (kDefaultResolution)
  std::string gridSize = voxcli::formatTriple(vox::kDefaultBlockWorldGrid);  // block maps: the world grid X,Y,Z
  std::optional<std::string> extent;  // demo:city: voxels X,Y,Z; none = vox::kCityDefaultExtent
  double voxelSize = 0;               // world units per voxel; 0 = not given (use the resolution)
  std::string gridName;
  std::optional<double> threshold;
  vox::FillMode fill = vox::FillMode::Surface;
  vox::SolidRule solidRule = vox::SolidRule::Winding;
  VoxelizeMethod method = VoxelizeMethod::Exact;
  std::string bounds;
  uint32_t pad = 0;
  std::string classes;
  bool dropInvalid = false;
  bool ignoreMissingMaterials = false;
  bool check = false;
  std::string region;     // --region I/N: tile I of N of the world (libvox/core/regions.h)
  std::string regionBox;  // --region-box umin,vmin,wmin,umax,vmax,wmax: an aligned index box
  CommonOptions common;
  const CLI::App* app = nullptr;  // to tell an option given from its default (checkVoxelizeOptions)

  bool isRegionBake() const { return !region.empty() || !regionBox.empty(); }

  /// Voxels on the longest side: the given resolution, else the default.
  uint32_t resolutionOrDefault() const { return resolution ? resolution : kDefaultResolution; }
  /// For inputs placed by resolution or voxel size: the resolution, or 0 when
  /// a voxel size is given.
  uint32_t resolutionUnlessVoxelSize() const { return voxelSize > 0 ? 0 : resolutionOrDefault(); }
  /// demo:city's extent: --extent parsed and checked (vox::Error Usage), else the default.
  std::array<uint32_t, 3> cityExtent() const;
};

/// Adds the `voxelize` subcommand and every option to `root`, filling `opts`.
CLI::App* addVoxelizeCommand(CLI::App& root, VoxelizeOptions& opts);

/// Checks what holds for every input kind (--res vs --voxel-size, *.vdb output,
/// input combinations); throws vox::Error (Usage).
void checkVoxelizeOptions(const VoxelizeOptions& o);
bool allInputsAreMeshes(const VoxelizeOptions& o);
/// True when the light module can run this command line: meshes only, the
/// exact method, no --check.
bool isLightBake(const VoxelizeOptions& o);

/// The region record of a region bake (--region or --region-box) of a world
/// with `header` (dims, placement, classes, sources: the whole bake's) and the
/// settings text (voxelSettingsText); nullopt without those options. Throws
/// vox::Error (Usage) for a box that is not aligned (naming the nearest aligned
/// box) or does not fit in the dims.
std::optional<vox::SceneRegion> regionRecord(const VoxelizeOptions& o, const vox::SceneHeader& header,
                                             const std::string& settings);

/// The canonical text of every option that changes a bake's voxels beyond
/// what the scene header records (fill, solid rule, method, class rules'
/// digest, files a mesh names, grid name, threshold, block-world grid,
/// resolution...), for the region bake's world key: the one place it is made.
/// `filesRead`: files the inputs named (OBJ mtllib, textures, glTF buffers).
std::string voxelSettingsText(const VoxelizeOptions& o, const std::vector<std::string>& filesRead = {});

/// The meshes read, classes assigned and the scene placed: the "parse" and
/// "prepare" phases of a mesh bake.
struct PreparedMeshes {
  vox::Mesh mesh;
  std::vector<uint8_t> triangleClass;
  vox::SceneHeader header;
  std::vector<std::string> warnings;
  std::vector<std::string> filesRead;  // files the inputs named (mtllib, textures, buffers)
  uint64_t bytesRead = 0;
};
/// `deferred`: a single glTF input's colour textures are left undecoded there,
/// for the bake to read by rows (formats/mesh/deferred_textures.h).
PreparedMeshes prepareMeshes(const VoxelizeOptions& o, Run& run, vox::DeferredTextures* deferred = nullptr);

/// The memory guard of a mesh bake (libvox/mesh/voxelize_memory.h): estimates
/// the peak before the work and refuses, with the largest --res (or the
/// smallest --voxel-size) that fits, when it exceeds --max-memory. `openvdb`:
/// the bake builds OpenVDB trees (--method sdf, --check), not only blocks.
/// `deferred`: the rows of textures the bake reads count too.
void checkMeshBakeMemory(const VoxelizeOptions& o, Run& run, const PreparedMeshes& p, bool openvdb,
                         const vox::DeferredTextures* deferred = nullptr);

/// Voxelizer settings from the options (fill mode, threads), reporting progress to `bar`.
vox::VoxelizeSettings voxelizeSettings(const VoxelizeOptions& o, const Run& run, ProgressBar& bar);

/// The counts and the closing message of a mesh bake, then run.finish().
/// `deferred`: textures decoded during the bake, counted as "texture_decode".
int finishMeshBake(const VoxelizeOptions& o, Run& run, const PreparedMeshes& p, uint64_t occupied, uint64_t surface,
                   size_t classesPresent, const vox::DeferredTextures* deferred = nullptr);

/// The mesh bake without OpenVDB: prepare, voxelize into blocks, write the
/// .vdb directly (formats/scene/scene_vdb_direct.h), report. Returns the exit code.
int runMeshesDirect(const VoxelizeOptions& o, Run& run, const std::string& outputTemp);

/// --fill's names (surface | solid), shared with `vox mip --source-fill`.
inline const EnumNames<vox::FillMode>& fillModeNames() {
  static const EnumNames<vox::FillMode> names{{"surface", vox::FillMode::Surface}, {"solid", vox::FillMode::Solid}};
  return names;
}

/// The light module's registration of `voxelize`.
Command registerVoxelizeLight(CLI::App& root);

/// vox's root description (both modules print it in --help).
extern const char* const kRootDescription;

}  // namespace voxcli
