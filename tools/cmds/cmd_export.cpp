// vox export INPUT -o OUT in the full module (docs/export.md): the command of
// export_command.h with what needs OpenVDB: pyramids and any scene
// readSceneVdb accepts as inputs, and OpenVDB fog volumes and level sets for
// renderers as outputs. The light module (export_main.cpp) runs the rest.
#include <CLI/CLI.hpp>

#include "formats/export/vdb_volume_writer.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "libvox/scene/class_volume_scene.h"
#include "libvox/scene/scene_grids.h"
#include "tools/cli/commands.h"
#include "tools/cmds/export_command.h"

namespace voxcli {

namespace {

/// A scene or a pyramid level, read with OpenVDB.
bool readVdbScene(const ExportOptions& o, const std::optional<vox::IndexBox>& region, bool withColor, Run& run,
                  ExportInput& in) {
  std::optional<vox::Scene> scene;
  if (vox::isPyramidVdb(o.input)) {
    in.kind = "pyramid";
    std::vector<vox::Scene> levels = vox::readPyramidVdb(o.input);
    if (o.level >= int(levels.size()))
      throwLevelOutOfRange(o.level, o.input, levels.size());
    scene.emplace(std::move(levels[size_t(o.level)]));
  } else {
    in.kind = "scene";
    if (o.level != 0)
      vox::throwUsage("--level " + std::to_string(o.level) + ": " + o.input +
                      " is a single scene; levels are in pyramids (vox mip) and page files (.vpk)");
    scene.emplace(vox::readSceneVdb(o.input));
  }
  const vox::SceneHeader& h = scene->header();
  in.dims = h.dims;
  in.frame.origin = h.origin;
  in.frame.voxelSize = h.voxelSize;
  in.classes = h.classes;
  in.box = regionIn(region, in.dims, o.input);
  if (withColor && !scene->hasColor())
    vox::throwBadInput(o.input + ": the scene has no baked colours; export the class palette (--color palette)");
  run.phase("volume");
  checkVolumeMemory(run, o.input, scene->grids().occupancy->tree().leafCount(), withColor);
  in.volume.emplace(vox::classVolumeFromScene(*scene, in.box, withColor, run.threads()));
  return true;
}

/// A fog volume or a level set of the occupancy, for renderers.
void exportVdbVolume(const ExportOptions& o, const ExportInput& in, Run& run) {
  const vox::VdbVolumeKind kind = o.fog ? vox::VdbVolumeKind::Fog : vox::VdbVolumeKind::LevelSet;
  // The float grid spans the leaves the band reaches, which grow with
  // --half-width: checked on them, before OpenVDB builds it.
  const uint64_t leaves = vox::vdbVolumeLeafCount(*in.volume, kind, o.halfWidth);
  const double resident = double(vox::residentBytesNow());
  vox::MemoryEstimate e;
  e.add("resident now", resident);
  e.add(o.fog ? "the fog volume" : "the level set and its working copies", vox::vdbVolumeWorkBytes(leaves, kind));
  std::string suggestion;  // a narrower band that fits, when the level set does not
  if (!o.fog && e.bytes() > run.memoryLimit().bytes && run.memoryLimit().bytes > 0 && o.halfWidth > 1)
    suggestion = suggestSetting("--half-width", 1, uint64_t(o.halfWidth - 1), run.memoryLimit(), [&](uint64_t hw) {
      return uint64_t(resident + vox::vdbVolumeWorkBytes(vox::vdbVolumeLeafCount(*in.volume, kind, int(hw)), kind));
    });
  run.checkMemory(e,
                  std::string(o.fog ? "a fog volume" : "a level set (--half-width " + std::to_string(o.halfWidth) + ")") +
                      " of " + o.input + " over " + counted(leaves, "leaf", "leaves") + " of 8^3",
                  suggestion);
  run.phase("write");
  const vox::VdbVolumeResult r =
      vox::writeVdbVolume(*in.volume, in.frame, kind, o.halfWidth, run.output(o.output));
  nlohmann::json& c = run.counts();
  c["grid"] = o.fog ? "density" : "surface";
  c["active_voxels"] = r.activeVoxels;
  if (r.activeVoxels) c["active_box"] = boxJson(r.activeBox);
  if (o.levelSet) c["half_width"] = o.halfWidth;
  c["bytes"] = r.bytes;
  run.noteWhenDone("wrote " + o.output + ": " + (o.fog ? "fog volume" : "level set") + ", " +
           counted(r.activeVoxels, "active voxel", "active voxels"));
}

}  // namespace

Command registerExport(CLI::App& root) {
  auto opts = std::make_shared<ExportOptions>();
  CLI::App* cmd = addExportOptions(root, *opts);
  return {cmd, [opts] {
            const ExportBackend full{readVdbScene, exportVdbVolume, {}};
            const std::optional<int> code = runExport(*opts, full);
            if (!code) throw vox::Error(vox::ErrorKind::Internal, "export: the full module declined the command");
            return *code;
          }};
}

}  // namespace voxcli
