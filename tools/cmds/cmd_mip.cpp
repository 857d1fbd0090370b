// vox mip SCENE.vdb -o PYRAMID.vdb: the LOD pyramid (libvox/scene/mip.h), in one file
// (formats/scene/SCENE.md "Pyramids") or one scene file per level (--split), with the
// error of every level against a direct voxelization of the source (--source).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "formats/core/file_util.h"
#include "formats/core/file_kinds.h"
#include "formats/mesh/mesh_input.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/mesh/class_mapping.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/core/error.h"
#include "libvox/scene/mip.h"
#include "libvox/scene/voxelize_scene.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/enum_option.h"
#include "tools/cmds/mip_light.h"
#include "tools/cmds/option_names.h"

namespace voxcli {

namespace {

/// Why a level has no IoU: an empty reference makes the ratio meaningless (0
/// for any non-empty level), so the report says so instead of a number.
constexpr const char* kNoReferenceVoxels = "no reference voxels";

nlohmann::json comparisonJson(const vox::MipComparison& c) {
  const bool noReference = c.referenceVoxels == 0;
  return {{"iou", noReference ? nlohmann::json(nullptr) : nlohmann::json(c.iou)},
          {"iou_reason", noReference ? nlohmann::json(kNoReferenceVoxels) : nlohmann::json(nullptr)},
          {"class_disagreement", c.classDisagreement},
          {"mip_voxels", c.mipVoxels},
          {"reference_voxels", c.referenceVoxels},
          {"both", c.both},
          {"only_mip", c.onlyMip},
          {"only_reference", c.onlyReference},
          {"class_disagree_voxels", c.classDisagree}};
}

int runMip(const MipOptions& o) {
  if (!o.split && !vox::hasExtension(o.output, ".vdb"))
    vox::throwUsage("-o " + o.output + ": the pyramid is written as OpenVDB; name it *.vdb (or give --split for one "
                    "file per level, OUT.mip1.vdb ...)");
  const std::string stem = o.split ? splitStem(o.output) : std::string();
  if (o.split && (stem.empty() || stem.back() == '/'))
    vox::throwUsage("-o " + o.output + ": with --split, give a file name stem (OUT writes OUT.mip1.vdb ...)");
  if (o.levels < 0) vox::throwUsage("--levels must be >= 0 (0 = automatic)");

  Run run("mip", o.common);
  const std::string outTemp = startMipRun(o, run);
  vox::Scene base = vox::readSceneVdb(o.input);
  checkMipInput(o, base.header().mipLevel, run);
  run.phase("reduce");
  vox::MipSettings settings;
  settings.occupancy = o.occupancy;
  settings.levels = o.levels;
  settings.threads = run.threads();
  nlohmann::json perLevel = nlohmann::json::array();
  settings.onLevel = [&](int n, const vox::Scene& s, double secs) {
    const vox::Dims d = s.header().dims;
    const uint64_t surface = vox::surfaceCount(s);
    perLevel.push_back({{"level", s.header().mipLevel},
                        {"dims", {d.x, d.y, d.z}},
                        {"voxel_size", s.header().voxelSize},
                        {"occupied", s.occupiedCount()},
                        {"surface", surface},
                        {"classes_present", s.classesPresent().size()},
                        {"seconds", secs}});
    (void)n;
  };
  std::vector<vox::Scene> levels = vox::buildMipPyramid(base, settings);

  // Error against direct voxelizations of the source at each level's placement.
  if (!o.sources.empty()) {
    run.phase("compare");
    nlohmann::json errors = nlohmann::json::array();
    std::vector<vox::Scene> refScenes;  // .vdb sources
    std::vector<std::string> refNames;
    std::optional<vox::Mesh> mesh;
    std::string meshName;
    for (const std::string& src : o.sources) {
      if (src == vox::kHamletName) continue;
      if (vox::isDemoName(src))
        vox::throwUsage("--source " + src + ": the built-in scene is " + std::string(vox::kHamletName));
      run.input(src);
      vox::requireRegularFile(src);
      if (vox::fileKindOf(src) == vox::FileKind::Mesh) {
        if (mesh) vox::throwUsage("--source: give one mesh");
        std::vector<std::string> warnings;
        mesh = vox::readMeshFile(src, vox::MeshReadOptions{}, warnings);
        for (const std::string& f : mesh->filesRead) run.input(f);
        meshName = src;
      } else if (vox::looksLikeVdb(src)) {
        refScenes.push_back(vox::readSceneVdb(src));
        refNames.push_back(src);
      } else {
        throw vox::Error(vox::ErrorKind::BadInput, src + ": --source takes " + vox::kHamletName + ", " +
                                                       vox::describe(vox::FileKind::Mesh) + " or a scene .vdb");
      }
    }
    const bool demo = std::find(o.sources.begin(), o.sources.end(), vox::kHamletName) != o.sources.end();
    std::vector<bool> refUsed(refScenes.size(), false);
    for (const vox::Scene& level : levels) {
      const vox::SceneHeader& h = level.header();
      auto record = [&](const std::string& ref, const vox::MipComparison& c) {
        nlohmann::json j = comparisonJson(c);
        j["level"] = h.mipLevel;
        j["reference"] = ref;
        errors.push_back(j);
        char line[200];
        if (c.referenceVoxels == 0)
          std::snprintf(line, sizeof line, "level %d against %s: %s (the level has %llu)", h.mipLevel, ref.c_str(),
                        kNoReferenceVoxels, (unsigned long long)c.mipVoxels);
        else
          std::snprintf(line, sizeof line, "level %d against %s: IoU %.4f, class differs at %.2f%% of shared voxels",
                        h.mipLevel, ref.c_str(), c.iou, 100.0 * c.classDisagreement);
        run.note(line);
      };
      if (demo) {
        if (h.dims.x != h.dims.y || h.dims.x != h.dims.z) {
          errors.push_back({{"level", h.mipLevel}, {"reference", vox::kHamletName}, {"skipped", "dims are not a cube"}});
        } else {
          vox::HamletOptions ho;
          ho.resolution = h.dims.x;
          ho.threads = run.threads();
          const vox::Scene ref = vox::buildHamlet(ho);
          const std::string why = vox::placementMismatch(h, ref.header());
          if (!why.empty())
            errors.push_back({{"level", h.mipLevel},
                              {"reference", std::string(vox::kHamletName) + " --res " + std::to_string(h.dims.x)},
                              {"skipped", "placement differs: " + why}});
          else
            record(std::string(vox::kHamletName) + " --res " + std::to_string(h.dims.x), vox::compareWithReference(level, ref));
        }
      }
      for (size_t i = 0; i < refScenes.size(); ++i)
        if (vox::placementMismatch(h, refScenes[i].header()).empty()) {
          refUsed[i] = true;
          record(refNames[i], vox::compareWithReference(level, refScenes[i]));
        }
      if (mesh) {
        vox::SceneHeader rh = h;
        rh.mipLevel = 0;
        const vox::ClassMapping mapping = vox::classPerMaterial(*mesh, meshName);
        rh.classes = mapping.table;
        vox::VoxelizeSettings vs;
        vs.fill = o.sourceFill;
        vs.threads = run.threads();
        const vox::Scene ref = vox::voxelizeMesh(*mesh, vox::assignClasses(*mesh, mapping), rh, vs);
        record(meshName + " (" + nameOf(fillModeNames(), o.sourceFill) + ")", vox::compareWithReference(level, ref));
      }
    }
    for (size_t i = 0; i < refScenes.size(); ++i)
      if (!refUsed[i])
        run.note("warning: --source scene " + vox::toString(refScenes[i].header().dims) +
                 " matches the placement of no level; not compared");
    run.error()["levels"] = errors;
  }

  run.phase("write");
  if (o.split) {
    for (const vox::Scene& level : levels) {
      const std::string path = splitName(stem, level.header().mipLevel);
      vox::writeSceneVdb(level, run.output(path));
    }
  } else {
    std::vector<const vox::Scene*> all{&base};
    for (const vox::Scene& l : levels) all.push_back(&l);
    vox::writePyramidVdb(all, o.occupancy, outTemp);
  }
  reportMip(o, perLevel, levels.size(), base.occupiedCount(), run);
  return run.finish();
}

}  // namespace

Command registerMip(CLI::App& root) {
  auto opts = std::make_shared<MipOptions>();
  CLI::App* cmd = addMipOptions(root, *opts);
  return {cmd, [opts] { return runMip(*opts); }};
}

}  // namespace voxcli
