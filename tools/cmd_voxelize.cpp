// vox voxelize: inputs (the built-in demo scene, seed 002 block maps) -> scene.vdb.
#include <CLI/CLI.hpp>
#include <filesystem>

#include "formats/blockmap_json.h"
#include "formats/scene_vdb.h"
#include "formats/vdb_grid_input.h"
#include "libvox/demo_hamlet.h"
#include "libvox/error.h"
#include "tools/cli.h"
#include "tools/commands.h"

namespace voxcli {

namespace {

struct VoxelizeOptions {
  std::vector<std::string> inputs;
  std::string output;
  uint32_t resolution = 0;  // 0 = the input's default (demo: 256)
  std::string gridSize = "64,48,64";
  double voxelSize = 0;
  std::string gridName;
  std::optional<double> threshold;
  CommonOptions common;
};

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  for (char& c : tail) c = char(std::tolower(static_cast<unsigned char>(c)));
  return tail == suffix;
}

int runVoxelize(const VoxelizeOptions& o) {
  if (o.voxelSize > 0 && o.resolution)
    throw vox::Error(vox::ErrorKind::Usage, "give --res or --voxel-size, not both");
  if (!endsWith(o.output, ".vdb"))
    throw vox::Error(vox::ErrorKind::Usage, "-o " + o.output + ": the scene is written as OpenVDB; name it *.vdb");
  if (o.inputs.size() != 1)
    throw vox::Error(vox::ErrorKind::Usage,
                     "this version combines no inputs yet: give exactly one of demo:hamlet or a map.json");
  const std::string& input = o.inputs[0];
  Run run("voxelize", o.common);
  const std::string outputTemp = run.output(o.output);  // checks the destination before the work
  std::optional<vox::Scene> scene;
  if (input.rfind("demo:", 0) == 0) {
    if (input != "demo:hamlet")
      throw vox::Error(vox::ErrorKind::Usage, "unknown demo scene '" + input + "'; the built-in scene is demo:hamlet");
    run.phase("generate");
    vox::HamletOptions h;
    h.resolution = o.resolution ? o.resolution : 256;
    h.threads = run.threads();
    auto bar = run.progress("hamlet");
    h.progress = [&bar](double f) { bar->update(f); };
    scene = vox::buildHamlet(h);
    bar->done();
  } else if (endsWith(input, ".json")) {
    if (o.resolution)
      throw vox::Error(vox::ErrorKind::Usage, "--res does not apply to block maps: one block is one voxel");
    run.phase("parse");
    run.input(input);
    vox::BlockMapOptions b;
    b.gridSize = parseTriple(o.gridSize, "--grid-size");
    scene = vox::readBlockMap(input, b);
  } else if (endsWith(input, ".vdb")) {
    run.phase("resample");
    run.input(input);
    vox::VdbGridInputOptions v;
    v.gridName = o.gridName;
    v.threshold = o.threshold;
    v.voxelSize = o.voxelSize;
    v.resolution = o.voxelSize > 0 ? o.resolution : (o.resolution ? o.resolution : 256);
    v.threads = run.threads();
    auto bar = run.progress("resample");
    v.progress = [&bar](double f) { bar->update(f); };
    scene = vox::readVdbGridAsScene(input, v);
    bar->done();
  } else {
    if (!std::filesystem::exists(input))
      throw vox::Error(vox::ErrorKind::BadInput, input + ": no such file");
    throw vox::Error(vox::ErrorKind::BadInput,
                     input + ": unsupported input; this version of vox reads demo:hamlet, seed 002 block maps "
                             "(*.json) and OpenVDB grids (*.vdb); mesh inputs are not implemented yet");
  }
  run.phase("write");
  vox::writeSceneVdb(*scene, outputTemp);
  const vox::SceneStats stats = scene->stats();
  const vox::Dims d = scene->header().dims;
  run.counts()["dims"] = {d.x, d.y, d.z};
  run.counts()["occupied_voxels"] = stats.occupied;
  run.counts()["surface_voxels"] = stats.surface;
  run.counts()["classes_present"] = scene->classesPresent().size();
  run.note("wrote " + o.output + ": " + vox::toString(d) + ", " + std::to_string(stats.occupied) +
           " occupied voxels, " + std::to_string(scene->classesPresent().size()) + " classes");
  return run.finish();
}

}  // namespace

Command registerVoxelize(CLI::App& root) {
  auto opts = std::make_shared<VoxelizeOptions>();
  CLI::App* cmd = root.add_subcommand("voxelize", "Bake inputs into a scene (.vdb)");
  cmd->footer(
      "Inputs:\n"
      "  demo:hamlet   the built-in procedural hamlet (resolution^3 voxels, --res, default 256)\n"
      "  MAP.json      a seed 002 block map: one voxel per block, dims = largest position + 1,\n"
      "                world placement from worldScale and --grid-size\n"
      "  GRID.vdb      an OpenVDB level set (inside: value <= 0) or fog volume (--threshold T:\n"
      "                inside where value >= T), resampled at --res (default 256) or --voxel-size\n"
      "Example: vox voxelize demo:hamlet --res 128 -o hamlet.vdb");
  cmd->add_option("inputs", opts->inputs, "demo:hamlet or a map.json")->required();
  cmd->add_option("-o,--output", opts->output, "Scene file to write (*.vdb)")->required();
  cmd->add_option("--res", opts->resolution, "Voxels on the longest axis (demo: default 256)")
      ->check(CLI::Range(1u, 4096u));
  cmd->add_option("--grid-size", opts->gridSize, "Block-map world grid X,Y,Z (seed 002)")
      ->capture_default_str();
  cmd->add_option("--voxel-size", opts->voxelSize, "World units per voxel (instead of --res)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--grid", opts->gridName, ".vdb input: the grid to read (default: the first float grid)");
  cmd->add_option("--threshold", opts->threshold, ".vdb fog volume: inside where value >= T");
  addCommonOptions(*cmd, opts->common);
  return {cmd, [opts] { return runVoxelize(*opts); }};
}

}  // namespace voxcli
