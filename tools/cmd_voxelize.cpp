// vox voxelize: inputs (the built-in demo scene, seed 002 block maps) -> scene.vdb.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <limits>

#include "formats/blockmap_json.h"
#include "formats/scene_vdb.h"
#include "formats/classes_json.h"
#include "formats/mesh_input.h"
#include "formats/vdb_grid_input.h"
#include "libvox/placement.h"
#include "libvox/sha256.h"
#include "libvox/voxelize.h"
#include "libvox/voxelize_check.h"
#include "libvox/voxelize_sdf.h"
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

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  for (char& c : tail) c = char(std::tolower(static_cast<unsigned char>(c)));
  return tail == suffix;
}

std::array<double, 6> parseBounds(const std::string& text) {
  std::array<double, 6> b{};
  size_t pos = 0;
  for (int i = 0; i < 6; ++i) {
    const size_t end = text.find(',', pos);
    if ((i < 5) != (end != std::string::npos))
      throw vox::Error(vox::ErrorKind::Usage, "--bounds expects xmin,ymin,zmin,xmax,ymax,zmax, got '" + text + "'");
    const std::string part = text.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    char* stop = nullptr;
    b[size_t(i)] = std::strtod(part.c_str(), &stop);
    if (part.empty() || *stop != '\0')
      throw vox::Error(vox::ErrorKind::Usage, "--bounds expects six numbers, got '" + text + "'");
    pos = end + 1;
  }
  return b;
}

int runMeshes(const VoxelizeOptions& o, Run& run, const std::string& outputTemp) {
  if (o.fill != "surface" && o.fill != "solid")
    throw vox::Error(vox::ErrorKind::Usage, "--fill " + o.fill + ": expected surface or solid");
  if (o.method != "exact" && o.method != "sdf")
    throw vox::Error(vox::ErrorKind::Usage, "--method " + o.method + ": expected exact or sdf");
  run.phase("parse");
  vox::MeshReadOptions ro;
  ro.dropInvalid = o.dropInvalid;
  ro.ignoreMissingMaterials = o.ignoreMissingMaterials;
  std::vector<std::string> warnings;
  vox::Mesh mesh;
  uint64_t bytesRead = 0;
  for (const std::string& in : o.inputs) {
    run.input(in);
    const int64_t size = vox::fileSizeOrMinusOne(in);
    if (size < 0) throw vox::Error(vox::ErrorKind::BadInput, in + ": no such file");
    bytesRead += uint64_t(size);
    vox::Mesh m = vox::readMeshFile(in, ro, warnings);
    for (const std::string& f : m.filesRead) run.input(f);
    if (o.inputs.size() == 1) mesh = std::move(m);
    else mesh.append(m);
  }
  for (const std::string& w : warnings) run.note("warning: " + w);
  run.phase("prepare");  // classes, placement, provenance hashes
  if (mesh.triangles.empty())
    throw vox::Error(vox::ErrorKind::BadInput, o.inputs[0] + (o.inputs.size() > 1 ? " (and the other inputs)" : "") +
                                                   ": no triangles; there is nothing to voxelize");
  // Classes: from --classes, else one per material.
  vox::ClassMapping mapping = o.classes.empty() ? vox::classPerMaterial(mesh, o.inputs[0]) : vox::readClassMapping(o.classes);
  if (!o.classes.empty()) run.input(o.classes);
  const std::vector<uint8_t> triClass = vox::assignClasses(mesh, mapping);
  // Placement.
  vox::SceneHeader header;
  std::array<double, 3> lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  std::array<double, 3> hi{-lo[0], -lo[1], -lo[2]};
  for (const auto& tri : mesh.triangles)
    for (uint32_t vi : tri)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], mesh.positions[vi][k]), hi[k] = std::max(hi[k], mesh.positions[vi][k]);
  vox::PlacementOptions place;
  place.voxelSize = o.voxelSize;
  place.resolution = o.voxelSize > 0 ? 0 : (o.resolution ? o.resolution : 256);
  place.pad = o.pad;
  if (!o.bounds.empty()) place.bounds = parseBounds(o.bounds);
  vox::placeGrid(lo, hi, place, header);
  header.classes = mapping.table;
  for (const std::string& in : o.inputs) {
    uint64_t bytes = 0;
    const std::string sha = vox::sha256File(in, &bytes);
    header.sources.push_back({in, "mesh", sha, bytes});
  }
  run.phase("voxelize");
  vox::VoxelizeSettings settings;
  settings.fill = o.fill == "solid" ? vox::FillMode::Solid : vox::FillMode::Surface;
  settings.threads = run.threads();
  auto bar = run.progress("voxelize");
  settings.progress = [&bar](double f) { bar->update(f); };
  vox::Scene scene = o.method == "sdf" ? vox::voxelizeMeshSdf(mesh, triClass, header, settings)
                                       : vox::voxelizeMesh(mesh, triClass, header, settings);
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
      // The winding-number reference costs (samples x triangles): keep it near 1e8 evaluations.
      const uint64_t samples = std::clamp<uint64_t>(uint64_t(1e8) / std::max<size_t>(1, mesh.triangles.size()), 500, 20000);
      const vox::SolidCheck c = vox::checkSolid(mesh, scene, samples);
      run.error()["solid"] = {{"mesh_volume", c.meshVolume}, {"voxel_volume", c.voxelVolume},
                              {"relative_volume_error", c.relativeVolumeError}, {"samples", c.samples}, {"iou", c.iou}};
    }
  }
  const uint64_t occupied = scene.occupiedCount(), surface = scene.surfaceCount();
  const vox::Dims d = scene.header().dims;
  run.counts() = {{"dims", {d.x, d.y, d.z}},      {"triangles", mesh.triangles.size()},
                  {"vertices", mesh.positions.size()}, {"input_bytes", bytesRead},
                  {"occupied_voxels", occupied}, {"surface_voxels", surface},
                  {"classes_present", scene.classesPresent().size()}, {"method", o.method}, {"fill", o.fill},
                  {"warnings", warnings}};
  run.note("wrote " + o.output + ": " + vox::toString(d) + ", " + std::to_string(occupied) + " occupied voxels from " +
           std::to_string(mesh.triangles.size()) + " triangles");
  return run.finish();
}

int runVoxelize(const VoxelizeOptions& o) {
  if (o.voxelSize > 0 && o.resolution)
    throw vox::Error(vox::ErrorKind::Usage, "give --res or --voxel-size, not both");
  if (!endsWith(o.output, ".vdb"))
    throw vox::Error(vox::ErrorKind::Usage, "-o " + o.output + ": the scene is written as OpenVDB; name it *.vdb");
  const bool allMeshes = std::all_of(o.inputs.begin(), o.inputs.end(), [](const std::string& i) { return vox::isMeshFile(i); });
  if (o.inputs.size() != 1 && !allMeshes)
    throw vox::Error(vox::ErrorKind::Usage,
                     "several inputs combine only when all are meshes (.obj .ply .stl .gltf .glb); demo:hamlet, "
                     "map.json and .vdb inputs go one at a time");
  const std::string& input = o.inputs[0];
  Run run("voxelize", o.common);
  const std::string outputTemp = run.output(o.output);  // checks the destination before the work
  std::optional<vox::Scene> scene;
  if (allMeshes) {
    return runMeshes(o, run, outputTemp);
  } else if (input.rfind("demo:", 0) == 0) {
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
                     input + ": unsupported input; vox voxelize reads meshes (.obj .ply .stl .gltf .glb), demo:hamlet, "
                             "seed 002 block maps (*.json) and OpenVDB grids (*.vdb)");
  }
  run.phase("write");
  vox::writeSceneVdb(*scene, outputTemp);
  const uint64_t occupied = scene->occupiedCount();
  const vox::Dims d = scene->header().dims;
  run.counts()["dims"] = {d.x, d.y, d.z};
  run.counts()["occupied_voxels"] = occupied;
  run.counts()["surface_voxels"] = scene->surfaceCount();
  run.counts()["classes_present"] = scene->classesPresent().size();
  run.note("wrote " + o.output + ": " + vox::toString(d) + ", " + std::to_string(occupied) +
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
      "  MESH...       .obj .ply .stl .gltf .glb (several combine into one scene), --res N on the\n"
      "                longest side (default 256), --fill surface|solid, --classes FILE.json\n"
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
  cmd->add_option("--fill", opts->fill, "Meshes: surface (voxels a triangle touches) or solid (plus the inside)")
      ->capture_default_str();
  cmd->add_option("--method", opts->method, "Meshes: exact (default) or sdf (OpenVDB meshToVolume, for comparison)")
      ->capture_default_str();
  cmd->add_option("--bounds", opts->bounds, "Meshes: world box xmin,ymin,zmin,xmax,ymax,zmax to voxelize");
  cmd->add_option("--pad", opts->pad, "Meshes: empty voxels added on every side");
  cmd->add_option("--classes", opts->classes, "Meshes: JSON mapping material/mesh/node names to classes");
  cmd->add_flag("--drop-invalid", opts->dropInvalid, "Meshes: drop triangles with NaN/Inf vertices instead of failing");
  cmd->add_flag("--ignore-missing-materials", opts->ignoreMissingMaterials,
                "OBJ: a missing mtllib or map_Kd file is a warning (materials keep their names) instead of an error");
  cmd->add_flag("--check", opts->check, "Meshes: measure the error against exact references (into --report)");
  addCommonOptions(*cmd, opts->common);
  return {cmd, [opts] { return runVoxelize(*opts); }};
}

}  // namespace voxcli
