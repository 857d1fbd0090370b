// vox voxelize: inputs (meshes, the built-in demo scene, block maps, OpenVDB grids) -> scene.vdb.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <limits>

#include "formats/core/file_util.h"
#include "formats/core/file_kinds.h"
#include "formats/vdb/blockmap_json.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_grid_input.h"
#include "formats/scene/scene_vdb_direct.h"
#include "libvox/scene/scene_parts.h"
#include "libvox/scene/voxelize_scene.h"
#include "libvox/scene/voxelize_check.h"
#include "libvox/scene/voxelize_sdf.h"
#include "formats/scene/scene_vdb_direct.h"
#include "libvox/scene/demo_city.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/core/error.h"
#include "libvox/core/memory_budget.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/bake/voxelize_mesh.h"

namespace voxcli {

namespace {

// Meshes with --method sdf or --check need OpenVDB (meshToVolume, the scene
// queries of the checks); everything else takes the direct path, here too.
int runMeshes(const VoxelizeOptions& o, Run& run, const std::string& outputTemp) {
  if (isLightBake(o)) return runMeshesDirect(o, run, outputTemp);
  PreparedMeshes p = prepareMeshes(o, run);
  checkMeshBakeMemory(o, run, p, true);
  const vox::Mesh& mesh = p.mesh;
  run.phase("voxelize");
  auto bar = run.progress("voxelize");
  const vox::VoxelizeSettings settings = voxelizeSettings(o, run, *bar);
  vox::Scene scene = o.method == VoxelizeMethod::Sdf ? vox::voxelizeMeshSdf(mesh, p.triangleClass, p.header, settings)
                                       : vox::voxelizeMesh(mesh, p.triangleClass, p.header, settings);
  bar->done();
  run.phase("write");
  vox::writeSceneVdb(scene, outputTemp);
  if (o.check) {
    run.phase("check");
    if (settings.fill == vox::FillMode::Surface) {
      const vox::SurfaceCheck c = vox::checkSurface(mesh, scene, 200000);
      run.error()["surface"] = {{"triangles_checked", c.trianglesChecked}, {"oracle_voxels", c.oracleVoxels},
                                {"missed", c.missed}, {"extra", c.extra ? nlohmann::json(*c.extra) : nlohmann::json(nullptr)}};
    } else {
      // The winding-number reference costs (samples x triangles): about 5e8 solid angles, every
      // centre up to 128^3 (2.1 M) centres, at least 20000 centres.
      const uint64_t samples =
          std::clamp<uint64_t>(uint64_t(5e8) / std::max<size_t>(1, mesh.triangles.size()), 20000, uint64_t(1) << 21);
      const vox::SolidCheck c = vox::checkSolid(mesh, scene, samples, run.threads());
      run.error()["solid"] = {{"mesh_volume", c.meshVolume},     {"voxel_volume", c.voxelVolume},
                              {"relative_volume_error", c.relativeVolumeError},
                              {"iou", c.iou},                    {"samples", c.samples},
                              {"stride", c.stride},              {"missed", c.missed},
                              {"extra", c.extra},
                              {"reference", "interior (non-surface) voxel centres, |winding number| > 0.5"}};
    }
  }
  return finishMeshBake(o, run, p, scene.occupiedCount(), scene.surfaceCount(), scene.classesPresent().size());
}

/// A scene as the direct writer takes it: header and voxel blocks.
struct BakedScene {
  vox::SceneHeader header;
  vox::VoxelBlocks blocks;
};

/// demo:hamlet at the resolution given (or the default); a region bake
/// generates only its box (the surface test reads the design's neighbours).
BakedScene generateDemo(const VoxelizeOptions& o, Run& run, const std::string& input) {
  if (input != vox::kHamletName)
    throw vox::Error(vox::ErrorKind::Usage,
                     "unknown demo scene '" + input + "'; the built-in scenes are demo:hamlet and demo:city");
  const uint32_t res = o.resolutionOrDefault();
  vox::HamletOptions h;
  h.resolution = res;
  h.threads = run.threads();
  BakedScene out;
  h.box = vox::IndexBox{};  // empty: the header only
  (void)vox::buildHamletBlocks(h, out.header);
  out.header.region = regionRecord(o, out.header, voxelSettingsText(o));
  h.box.reset();
  double share = 1;  // of the world's x-z area
  if (out.header.region) {
    const vox::IndexBox& b = out.header.region->box;
    h.box = b;
    share = b.empty() ? 0.0
                      : double(b.max.u - b.min.u + 1) * double(b.max.v - b.min.v + 1) * double(b.max.w - b.min.w + 1) /
                            (double(res) * res * res);
  }
  // The memory guard: the hamlet fills a fixed share of its cube (ground,
  // buildings, trees), so its scene grows as res^3 plus a res^2 term (surfaces
  // and the builder's partly filled blocks), and the writer's file buffer and
  // first pages (4 MB), measured at 64..1024 (1.07-1.27x the peaks since the
  // writer holds a batch of leaf buffers, not whole grids; docs/reliability.md
  // "Memory"); a region holds its share of the volume.
  const uint64_t resident = vox::residentBytesNow();
  auto hamletAt = [resident, share](uint64_t r) {
    const double x = double(r);
    vox::MemoryEstimate e;
    e.add("resident before the bake", resident);
    e.add("hamlet scene", (0.56 * x * x * x + 100 * x * x) * share);
    e.add("scene writer", 4e6);
    return e;
  };
  run.checkMemory(hamletAt(res), "demo:hamlet at --res " + std::to_string(res),
                  suggestSetting("--res", 1, res, run.memoryLimit(), [&](uint64_t r) { return hamletAt(r).bytes(); }));
  run.phase("generate");
  auto bar = run.progress("hamlet");
  h.progress = [&bar](double f) { bar->update(f); };
  vox::SceneHeader header;
  out.blocks = vox::buildHamletBlocks(h, header);
  bar->done();
  return out;
}

/// demo:city at --extent: generated into blocks and written straight to the
/// .vdb (formats/scene/scene_vdb_direct.h), never as OpenVDB trees.
int runCity(const VoxelizeOptions& o, Run& run, const std::string& outputTemp) {
  vox::CityOptions c;
  c.extent = o.cityExtent();
  c.threads = run.threads();
  // A region bake generates its box only: the city's voxels are a function of
  // their coordinates and the surface test reads the design's neighbours, so
  // the part is the whole city cropped (libvox/scene/demo_city.h).
  vox::SceneHeader header = vox::cityHeader(c.extent);
  header.region = regionRecord(o, header, voxelSettingsText(o));
  if (header.region) c.box = header.region->box;
  run.phase("estimate");
  const uint64_t resident = vox::residentBytesNow();
  const vox::CityFootprint footprint = vox::estimateCityFootprint(c);
  vox::MemoryEstimate estimate;
  estimate.add("resident before the bake", resident);
  for (vox::MemoryPart& part : vox::cityBakeMemory(footprint).parts) estimate.parts.push_back(std::move(part));
  const std::string extentText = formatTriple(c.extent);
  std::string suggestion;
  if (!run.memoryLimit().unlimited() && estimate.bytes() > run.memoryLimit().bytes) {
    // The largest city with the same height and proportions that fits: the
    // horizontal sides scaled by k / 1024.
    auto scaled = [&](uint64_t k) {
      std::array<uint32_t, 3> e = c.extent;
      e[0] = uint32_t(std::max<uint64_t>(1, uint64_t(e[0]) * k / 1024));
      e[2] = uint32_t(std::max<uint64_t>(1, uint64_t(e[2]) * k / 1024));
      return e;
    };
    auto bytesAt = [&](uint64_t k) {
      vox::CityOptions s = c;
      s.extent = scaled(k);
      return resident + vox::cityBakeMemory(vox::estimateCityFootprint(s, 512)).bytes();
    };
    suggestion = suggestSetting("--extent", 1, 1023, run.memoryLimit(), bytesAt,
                                [&](uint64_t k) { return formatTriple(scaled(k)); });
  }
  run.checkMemory(estimate, "demo:city at --extent " + extentText, suggestion);

  run.phase("generate");
  auto bar = run.progress("city");
  c.progress = [&bar](double f) { bar->update(f); };
  vox::VoxelBlocks blocks = vox::buildCityBlocks(c);
  bar->done();
  const uint64_t blockCount = blocks.blockCount();
  run.phase("write");
  const vox::DirectWriteSummary s = vox::writeSceneVdbDirect(header, blocks, outputTemp, run.threads());
  const vox::Dims d = header.dims;
  run.counts()["dims"] = {d.x, d.y, d.z};
  run.counts()["voxel_size"] = header.voxelSize;
  run.counts()["occupied_voxels"] = s.occupied;
  run.counts()["surface_voxels"] = s.surface;
  run.counts()["classes_present"] = s.classesPresent.size();
  run.counts()["blocks"] = blockCount;
  run.counts()["file_bytes"] = s.fileBytes;
  run.counts()["estimated_occupied_voxels"] = uint64_t(footprint.occupied);
  run.counts()["estimated_blocks"] = uint64_t(footprint.blocks);
  if (header.region) {
    const vox::IndexBox& b = header.region->box;
    run.counts()["region"] = {{"index", header.region->index}, {"count", header.region->count},
                              {"box", b.empty() ? nlohmann::json(nullptr)
                                                : nlohmann::json{b.min.u, b.min.v, b.min.w, b.max.u, b.max.v, b.max.w}}};
  }
  run.noteWhenDone("wrote " + o.output + ": " + vox::toString(d) + ", " + counted(s.occupied, "occupied voxel", "occupied voxels") +
           ", " + counted(s.classesPresent.size(), "class", "classes"));
  return run.finish();
}

/// A block map: one block is one voxel, placed in the world grid --grid-size.
vox::Scene readBlockMapInput(const VoxelizeOptions& o, Run& run, const std::string& input) {
  // --res and --voxel-size were refused up front (checkVoxelizeOptions).
  run.phase("parse");
  run.input(input);
  {
    // The memory guard: the JSON document (nlohmann's tree: ~10 bytes per
    // byte of text) and the scene of its blocks (one voxel per ~45 bytes of
    // text, in partly filled 8^3 leaves), measured (docs/reliability.md "Memory").
    const int64_t size = vox::fileSizeOrMinusOne(input);
    vox::MemoryEstimate e;
    e.add("resident before reading", vox::residentBytesNow());
    e.add("JSON document", double(std::max<int64_t>(0, size)) * 12.0);
    e.add("scene", double(std::max<int64_t>(0, size)) * 4.0);
    run.checkMemory(e, "reading the block map " + input);
  }
  vox::BlockMapOptions b;
  b.gridSize = parseTriple(o.gridSize, "--grid-size");
  return vox::readBlockMap(input, b);
}

/// An OpenVDB level set or fog volume, resampled at the resolution or voxel size.
vox::Scene resampleGrid(const VoxelizeOptions& o, Run& run, const std::string& input,
                        std::optional<vox::SceneRegion>* region = nullptr) {
  run.phase("resample");
  run.input(input);
  vox::VdbGridInputOptions v;
  v.gridName = o.gridName;
  v.threshold = o.threshold;
  v.voxelSize = o.voxelSize;
  v.resolution = o.resolutionUnlessVoxelSize();
  v.threads = run.threads();
  if (region)  // a region bake resamples its box only
    v.regionOf = [&o, region](const vox::SceneHeader& world) -> std::optional<vox::IndexBox> {
      *region = regionRecord(o, world, voxelSettingsText(o));
      return *region ? std::optional<vox::IndexBox>((*region)->box) : std::nullopt;
    };
  auto bar = run.progress("resample");
  v.progress = [&bar](double f) { bar->update(f); };
  vox::Scene scene = vox::readVdbGridAsScene(input, v);
  bar->done();
  return scene;
}

/// The scene of one input that is not a mesh, by its kind.
vox::Scene sceneOfInput(const VoxelizeOptions& o, Run& run, const std::string& input) {
  const std::optional<vox::FileKind> kind = vox::fileKindOf(input);
  if (kind == vox::FileKind::BlockMap) return readBlockMapInput(o, run, input);
  if (kind == vox::FileKind::Vdb) return resampleGrid(o, run, input);
  vox::requireRegularFile(input);
  throw vox::Error(vox::ErrorKind::BadInput,
                   input + ": unsupported input; vox voxelize reads " + vox::describe(vox::FileKind::Mesh) + ", " +
                       vox::describe(vox::FileKind::BlockMap) + ", an OpenVDB grid (.vdb), demo:hamlet or demo:city");
}

/// A non-mesh input as blocks: the demo and grids generated or resampled in
/// their region only (with the neighbours the surface flag reads), block maps
/// read whole and cropped to the region (the surface flag comes from the map's
/// neighbours, so the crop is exact).
BakedScene bakeInput(const VoxelizeOptions& o, Run& run, const std::string& input) {
  if (vox::isDemoName(input)) return generateDemo(o, run, input);
  BakedScene out;
  if (vox::fileKindOf(input) == vox::FileKind::Vdb) {
    std::optional<vox::SceneRegion> region;
    const vox::Scene scene = resampleGrid(o, run, input, &region);
    out.header = scene.header();
    out.header.region = region;
    out.blocks = vox::sceneBlocks(scene);
    return out;
  }
  const vox::Scene scene = sceneOfInput(o, run, input);
  out.header = scene.header();
  out.header.region = regionRecord(o, out.header, voxelSettingsText(o));
  out.blocks = out.header.region ? vox::sceneBlocks(scene, &out.header.region->box) : vox::sceneBlocks(scene);
  return out;
}

int runVoxelize(const VoxelizeOptions& o) {
  checkVoxelizeOptions(o);
  Run run("voxelize", o.common);
  const std::string outputTemp = run.output(o.output);  // checks the destination before the work
  if (allInputsAreMeshes(o)) return runMeshes(o, run, outputTemp);
  if (o.inputs[0] == vox::kCityName) return runCity(o, run, outputTemp);
  BakedScene baked = bakeInput(o, run, o.inputs[0]);
  run.phase("write");
  // The direct writer (the mesh bake's): the same bytes as OpenVDB's writer but
  // a UUID from the content, so a bake and a merge of its parts are byte-identical.
  const vox::DirectWriteSummary s = vox::writeSceneVdbDirect(baked.header, baked.blocks, outputTemp, run.threads());
  const vox::Dims d = baked.header.dims;
  run.counts()["dims"] = {d.x, d.y, d.z};
  run.counts()["occupied_voxels"] = s.occupied;
  run.counts()["surface_voxels"] = s.surface;
  run.counts()["classes_present"] = s.classesPresent.size();
  if (baked.header.region) {
    const vox::IndexBox& b = baked.header.region->box;
    run.counts()["region"] = {{"index", baked.header.region->index}, {"count", baked.header.region->count},
                              {"box", b.empty() ? nlohmann::json(nullptr)
                                                : nlohmann::json{b.min.u, b.min.v, b.min.w, b.max.u, b.max.v, b.max.w}}};
  }
  if (s.occupied == 0 && !baked.header.region)  // a region of the world may be empty; the whole world is worth a word
    run.note("warning: " + o.inputs[0] + " gave no occupied voxel at " + vox::toString(d) +
             ": the scene is empty" + (vox::isDemoName(o.inputs[0]) ? std::string(" (a finer --res resolves it)") : ""));
  run.noteWhenDone("wrote " + o.output + ": " + vox::toString(d) + ", " + counted(s.occupied, "occupied voxel", "occupied voxels") +
           ", " + counted(s.classesPresent.size(), "class", "classes"));
  return run.finish();
}

}  // namespace

Command registerVoxelize(CLI::App& root) {
  auto opts = std::make_shared<VoxelizeOptions>();
  CLI::App* cmd = addVoxelizeCommand(root, *opts);
  return {cmd, [opts] { return runVoxelize(*opts); }};
}

}  // namespace voxcli
