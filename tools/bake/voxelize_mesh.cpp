#include "tools/bake/voxelize_mesh.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <thread>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/mesh/classes_json.h"
#include "formats/mesh/deferred_textures.h"
#include "formats/mesh/mesh_input.h"
#include "formats/scene/scene_vdb_direct.h"
#include "libvox/mesh/class_compaction.h"
#include "libvox/mesh/class_mapping.h"
#include "libvox/core/error.h"
#include "libvox/mesh/placement.h"
#include "libvox/core/regions.h"
#include "libvox/core/sha256.h"
#include "libvox/mesh/voxelize.h"
#include "libvox/mesh/voxelize_memory.h"
#include "tools/cli/alloc_tuning.h"
#include "tools/cli/comma_list.h"
#include "tools/cli/enum_option.h"
#include "tools/cli/number_checks.h"

namespace voxcli {

const char* const kRootDescription =
    "vox: bake triangle meshes, OpenVDB grids and block maps into sparse voxel scenes, and\n"
    "turn scenes into atlases, bitmaps, LOD pyramids, page files and canonical renders.\n"
    "Exit codes: 0 ok, 1 check failed / differs, 2 usage, 3 bad input, 4 I/O or internal error.";

namespace {

std::array<double, 6> parseBounds(const std::string& text) {
  const std::vector<std::string> parts =
      splitCommaList(text, "--bounds", "xmin,ymin,zmin,xmax,ymax,zmax (six finite numbers)");
  if (parts.size() != 6)
    throw vox::Error(vox::ErrorKind::Usage, "--bounds expects xmin,ymin,zmin,xmax,ymax,zmax, got '" + text + "'");
  std::array<double, 6> b{};
  for (size_t i = 0; i < 6; ++i) {
    char* stop = nullptr;
    b[i] = std::strtod(parts[i].c_str(), &stop);
    if (*stop != '\0' || stop == parts[i].c_str() || !std::isfinite(b[i]))
      throw vox::Error(vox::ErrorKind::Usage, "--bounds expects six finite numbers, got '" + text + "'");
  }
  return b;
}

}  // namespace

const EnumNames<vox::SolidRule>& solidRuleNames() {
  static const EnumNames<vox::SolidRule> names{{"winding", vox::SolidRule::Winding}, {"parity", vox::SolidRule::Parity}};
  return names;
}

namespace {

const EnumNames<VoxelizeMethod>& methodNames() {
  static const EnumNames<VoxelizeMethod> names{{"exact", VoxelizeMethod::Exact}, {"sdf", VoxelizeMethod::Sdf}};
  return names;
}

/// libvox/scene/demo_hamlet.h's kHamletName (a header of the full module).
constexpr const char* kHamlet = "demo:hamlet";

/// ".obj .ply .stl .gltf .glb"
std::string meshExtensions() {
  std::string s;
  for (std::string_view e : vox::extensionsOf(vox::FileKind::Mesh)) s += (s.empty() ? "" : " ") + std::string(e);
  return s;
}

/// The SHA-256 of every input, computed on a second thread while the meshes
/// are parsed on this one (the files are in the page cache by then or soon
/// after). A plain std::thread, not a pool or a TBB task: one job whose point
/// is to overlap the parse, and a TBB task could wait for a free worker (with
/// --threads 1 there is none) and run only when joined, after the parse.
/// Errors surface, per input, when the sources are taken; the destructor
/// joins when something else failed first.
class InputHasher {
 public:
  explicit InputHasher(const std::vector<std::string>& inputs) : inputs_(inputs), hashes_(inputs.size()) {
    thread_ = std::thread([this] {
      for (size_t i = 0; i < inputs_.size(); ++i) try {
          hashes_[i].sha = vox::sha256File(inputs_[i], &hashes_[i].bytes);
        } catch (...) {
          hashes_[i].error = std::current_exception();
        }
    });
  }
  ~InputHasher() {
    if (thread_.joinable()) thread_.join();
  }
  InputHasher(const InputHasher&) = delete;
  InputHasher& operator=(const InputHasher&) = delete;

  /// Waits for the hashes; the scene's source records, in input order.
  std::vector<vox::SceneSource> sources() {
    thread_.join();
    std::vector<vox::SceneSource> out;
    for (size_t i = 0; i < inputs_.size(); ++i) {
      if (hashes_[i].error) std::rethrow_exception(hashes_[i].error);
      out.push_back({inputs_[i], "mesh", hashes_[i].sha, hashes_[i].bytes});
    }
    return out;
  }

 private:
  struct Hash {
    std::string sha;
    uint64_t bytes = 0;
    std::exception_ptr error;
  };
  const std::vector<std::string>& inputs_;
  std::vector<Hash> hashes_;
  std::thread thread_;
};

/// The "parse" phase: every input read and appended into one mesh, warnings
/// noted, inputs (and the files they name) recorded. `deferred`: a single
/// glTF input's colour textures decode there (texture indices are the
/// file's own, so only with one input).
void readMeshes(const VoxelizeOptions& o, Run& run, PreparedMeshes& p, vox::DeferredTextures* deferred) {
  run.phase("parse");
  vox::MeshReadOptions ro;
  ro.dropInvalid = o.dropInvalid;
  ro.ignoreMissingMaterials = o.ignoreMissingMaterials;
  for (const std::string& in : o.inputs) {
    run.input(in);
    const int64_t size = vox::fileSizeOrMinusOne(in);
    p.bytesRead += uint64_t(size);
    vox::Mesh m = vox::readMeshFile(in, ro, p.warnings, o.inputs.size() == 1 ? deferred : nullptr);
    for (const std::string& f : m.filesRead) run.input(f), p.filesRead.push_back(f);
    if (o.inputs.size() == 1) p.mesh = std::move(m);
    else p.mesh.append(m);
  }
  for (const std::string& w : p.warnings) run.note("warning: " + w);
}

/// Per-material class ids are derived, so a bake renumbers them densely; the
/// ids of a --classes file are the user's and stay.
vox::ClassIds classIdPolicy(const VoxelizeOptions& o) {
  return o.classes.empty() ? vox::ClassIds::Dense : vox::ClassIds::Keep;
}

/// The classes: from the --classes rules, else one per material.
vox::ClassMapping classMapping(const VoxelizeOptions& o, Run& run, const vox::Mesh& mesh) {
  vox::ClassMapping mapping = o.classes.empty() ? vox::classPerMaterial(mesh, o.inputs[0]) : vox::readClassMapping(o.classes);
  if (!o.classes.empty()) run.input(o.classes);
  return mapping;
}

/// Where the grid sits: the mesh's bounding box (or --bounds) at --res or
/// --voxel-size, with --pad. Refuses voxels too small for an OpenVDB transform.
void placeScene(const VoxelizeOptions& o, const vox::Mesh& mesh, vox::SceneHeader& header) {
  std::array<double, 3> lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  std::array<double, 3> hi{-lo[0], -lo[1], -lo[2]};
  for (const auto& tri : mesh.triangles)
    for (uint32_t vi : tri)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], mesh.positions[vi][k]), hi[k] = std::max(hi[k], mesh.positions[vi][k]);
  vox::PlacementOptions place;
  place.voxelSize = o.voxelSize;
  place.resolution = o.resolutionUnlessVoxelSize();
  place.pad = o.pad;
  if (!o.bounds.empty()) place.bounds = parseBounds(o.bounds);
  vox::placeGrid(lo, hi, place, header);
}

}  // namespace

CLI::App* addVoxelizeCommand(CLI::App& root, VoxelizeOptions& o) {
  const std::string res = std::to_string(VoxelizeOptions::kDefaultResolution);
  CLI::App* cmd = root.add_subcommand("voxelize", "Bake inputs into a scene (.vdb)");
  cmd->footer(
      "Inputs:\n"
      "  demo:hamlet   the built-in procedural hamlet (resolution^3 voxels, --res, default " + res + ")\n"
      "  demo:city     the built-in procedural city, 0.5 m voxels, --extent X,Y,Z voxels (default " +
      formatTriple(vox::kCityDefaultExtent) + ";\n"
      "                x, z up to " + std::to_string(vox::kCityMaxHorizontal) + ", y up to " +
      std::to_string(vox::kCityMaxHeight) + ")\n"
      "  MAP.json      a block map (map.json): one voxel per block, dims = largest position + 1,\n"
      "                world placement from worldScale and --grid-size\n"
      "  MESH...       " + meshExtensions() + " (several combine into one scene), --res N on the\n"
      "                longest side (default " + res + "), --fill surface|solid, --classes FILE.json\n"
      "  GRID.vdb      an OpenVDB level set (inside: value <= 0) or fog volume (--threshold T:\n"
      "                inside where value >= T), resampled at --res (default " + res + ") or --voxel-size\n"
      "Example: vox voxelize demo:hamlet --res 128 -o hamlet.vdb\n"
      "         vox voxelize demo:city --extent 4096,512,4096 -o city.vdb");
  cmd->add_option("inputs", o.inputs, "Meshes (" + meshExtensions() + "), demo:hamlet, demo:city, a map.json or a grid .vdb")->required();
  cmd->add_option("-o,--output", o.output, "Scene file to write (*.vdb)")->required();
  cmd->add_option("--res", o.resolution, "Voxels on the longest axis (default " + res + ")")->check(CLI::Range(1u, 4096u));
  cmd->add_option("--extent", o.extent,
                  "demo:city: voxels along x, y, z (default " + formatTriple(vox::kCityDefaultExtent) + ")");
  cmd->add_option("--grid-size", o.gridSize, "Block maps: the world grid X,Y,Z")->capture_default_str();
  cmd->add_option("--voxel-size", o.voxelSize, "World units per voxel (instead of --res)")->check(FinitePositive);
  cmd->add_option("--grid", o.gridName, ".vdb input: the grid to read (default: the first float grid)");
  cmd->add_option("--threshold", o.threshold, ".vdb fog volume: inside where value >= T")->check(Finite);
  addEnumOption(*cmd, "--fill", o.fill, fillModeNames(),
                "Meshes: surface (voxels a triangle touches) or solid (plus the inside)");
  addEnumOption(*cmd, "--solid-rule", o.solidRule, solidRuleNames(),
                "--fill solid: winding (|generalised winding number| > 0.5 at the voxel centre; default) or parity "
                "(2 of 3 axis rays; exact only on closed, consistently oriented meshes)");
  addEnumOption(*cmd, "--method", o.method, methodNames(),
                "Meshes: exact, or sdf (OpenVDB meshToVolume, for comparison)");
  cmd->add_option("--bounds", o.bounds, "Meshes: world box xmin,ymin,zmin,xmax,ymax,zmax to voxelize");
  cmd->add_option("--pad", o.pad, "Meshes: empty voxels added on every side");
  cmd->add_option("--classes", o.classes, "Meshes: JSON mapping material/mesh/node names to classes");
  cmd->add_flag("--drop-invalid", o.dropInvalid, "Meshes: drop triangles with NaN/Inf vertices and faces of fewer than 3 vertices instead of failing");
  cmd->add_flag("--ignore-missing-materials", o.ignoreMissingMaterials,
                "OBJ: a missing mtllib or map_Kd file is a warning (materials keep their names) instead of an error");
  cmd->add_flag("--check", o.check, "Meshes: measure the error against exact references (into --report)");
  cmd->add_option("--region", o.region,
                  "Bake only tile I of N (0-based) of the world's x-z tiling into a part (docs/scale.md); join the "
                  "parts with vox merge");
  cmd->add_option("--region-box", o.regionBox,
                  "Bake only the index box umin,vmin,wmin,umax,vmax,wmax (inclusive, on 32-voxel cells) into a part");
  addCommonOptions(*cmd, o.common);
  o.app = cmd;
  return cmd;
}

bool allInputsAreMeshes(const VoxelizeOptions& o) {
  return std::all_of(o.inputs.begin(), o.inputs.end(),
                     [](const std::string& i) { return vox::fileKindOf(i) == vox::FileKind::Mesh; });
}

std::array<uint32_t, 3> VoxelizeOptions::cityExtent() const {
  if (!extent) return vox::kCityDefaultExtent;
  const std::array<uint32_t, 3> e = parseTriple(*extent, "--extent");
  const std::string problem = vox::cityExtentProblem(e);
  if (!problem.empty()) throw vox::Error(vox::ErrorKind::Usage, "--extent " + *extent + ": " + problem);
  return e;
}

void checkVoxelizeOptions(const VoxelizeOptions& o) {
  const bool city = o.inputs.size() == 1 && o.inputs[0] == vox::kCityName;
  if (o.extent && !city)
    throw vox::Error(vox::ErrorKind::Usage, "--extent applies to demo:city only (block maps take --grid-size, "
                                            "the other inputs --res or --voxel-size)");
  if (city && (o.resolution || o.voxelSize > 0))
    throw vox::Error(vox::ErrorKind::Usage, std::string(o.resolution ? "--res" : "--voxel-size") +
                                                " does not apply to demo:city: its voxels are 0.5 m; size the city "
                                                "with --extent X,Y,Z (voxels)");
  if (city) o.cityExtent();  // refuses a bad --extent before any work
  if (o.voxelSize > 0 && o.resolution)
    throw vox::Error(vox::ErrorKind::Usage, "give --res or --voxel-size, not both");
  if (!vox::hasExtension(o.output, ".vdb"))
    throw vox::Error(vox::ErrorKind::Usage, "-o " + o.output + ": the scene is written as OpenVDB; name it *.vdb");
  if (!o.region.empty() && !o.regionBox.empty())
    throw vox::Error(vox::ErrorKind::Usage, "give --region or --region-box, not both");
  if (!o.region.empty()) (void)vox::parseRegionSpec(o.region);
  if (o.isRegionBake() && o.check)
    throw vox::Error(vox::ErrorKind::Usage,
                     "--check measures a whole bake; run it without --region (or check the merged scene)");
  if (o.isRegionBake() && o.method == VoxelizeMethod::Sdf)
    throw vox::Error(vox::ErrorKind::Usage,
                     "--method sdf is a comparison of whole bakes and has no region bake; use --method exact");
  if (o.inputs.size() != 1 && !allInputsAreMeshes(o))
    throw vox::Error(vox::ErrorKind::Usage,
                     "several inputs combine only when all are meshes (" + meshExtensions() + "); demo:hamlet, demo:city, "
                     "map.json and .vdb inputs go one at a time");
  // An option of another input kind would do nothing: refused, like --res on a
  // block map. Meshes refuse the grid and block-map options the same way (a
  // --threshold would also enter a region bake's world key, so parts baked with
  // and without it would not merge).
  auto given = [&o](const char* option) { return o.app && o.app->get_option(option)->count() > 0; };
  if (o.inputs.empty()) return;
  const std::string& input = o.inputs[0];
  auto refuse = [&](const std::string& option, const std::string& appliesTo, const std::string& what) {
    throw vox::Error(vox::ErrorKind::Usage, option + " applies to " + appliesTo + ", and " + what + ": drop " + option);
  };
  if (allInputsAreMeshes(o)) {
    const std::string what = o.inputs.size() == 1 ? input + " is a mesh" : "the inputs are meshes";
    for (const char* option : {"--grid", "--threshold"})
      if (given(option)) refuse(option, ".vdb grid inputs", what);
    if (given("--grid-size")) refuse("--grid-size", "block maps", what);
    if (given("--solid-rule") && o.fill != vox::FillMode::Solid)
      throw vox::Error(vox::ErrorKind::Usage, "--solid-rule decides the inside of --fill solid, and this bake is --fill "
                                              "surface (no inside is filled): add --fill solid, or drop --solid-rule");
    if (given("--solid-rule") && o.method == VoxelizeMethod::Sdf)
      throw vox::Error(vox::ErrorKind::Usage, "--solid-rule is the exact voxelizer's; --method sdf fills OpenVDB's "
                                              "inside mask whatever the rule: drop --solid-rule, or use --method exact");
    return;
  }
  const std::optional<vox::FileKind> kind = vox::fileKindOf(input);
  const bool demo = vox::isDemoName(input) || input == vox::kCityName;
  const bool grid = !demo && kind == vox::FileKind::Vdb;
  const bool map = !demo && kind == vox::FileKind::BlockMap;
  const std::string what = input + " is " + (demo ? "the built-in " + input : grid ? "an OpenVDB grid"
                                                                            : map ? "a block map" : "not a mesh");
  for (const char* option : {"--fill", "--solid-rule", "--method", "--bounds", "--pad", "--classes", "--drop-invalid",
                             "--ignore-missing-materials", "--check"})
    if (given(option)) refuse(option, "meshes", what);
  for (const char* option : {"--grid", "--threshold"})
    if (!grid && given(option)) refuse(option, ".vdb grid inputs", what);
  if (!map && given("--grid-size")) refuse("--grid-size", "block maps", what);
  // A block map's voxel is its block (worldScale world units), the hamlet's
  // 25.6 / --res: neither is placed by a voxel size.
  if (map && (o.resolution || o.voxelSize > 0)) {
    const std::string option = o.resolution ? "--res" : "--voxel-size";
    throw vox::Error(vox::ErrorKind::Usage, option + " does not apply to block maps: one block is one voxel, of the "
                                                     "map's worldScale; drop " + option);
  }
  if (input == kHamlet && o.voxelSize > 0)
    throw vox::Error(vox::ErrorKind::Usage, "--voxel-size does not apply to demo:hamlet: it spans 25.6 world units "
                                            "at --res N voxels (voxel size 25.6 / N); drop --voxel-size, or give --res");
}

bool isLightBake(const VoxelizeOptions& o) {
  return allInputsAreMeshes(o) && o.method == VoxelizeMethod::Exact && !o.check;
}

namespace {

/// "umin,vmin,wmin,umax,vmax,wmax" -> an inclusive box.
vox::IndexBox parseRegionBox(const std::string& text) {
  const std::vector<std::string> parts =
      splitCommaList(text, "--region-box", "umin,vmin,wmin,umax,vmax,wmax (six non-negative integers)");
  if (parts.size() != 6)
    throw vox::Error(vox::ErrorKind::Usage, "--region-box expects umin,vmin,wmin,umax,vmax,wmax, got '" + text + "'");
  int64_t v[6];
  for (size_t i = 0; i < 6; ++i) {
    char* stop = nullptr;
    v[i] = std::strtoll(parts[i].c_str(), &stop, 10);
    if (*stop != '\0' || stop == parts[i].c_str() || v[i] < 0 || v[i] > (int64_t(1) << 30))
      throw vox::Error(vox::ErrorKind::Usage,
                       "--region-box expects six non-negative integers (voxel indices), got '" + text + "'");
  }
  for (int i = 0; i < 3; ++i)
    if (v[i] > v[i + 3])
      throw vox::Error(vox::ErrorKind::Usage, "--region-box " + text + ": each min must be <= its max");
  return {{int32_t(v[0]), int32_t(v[1]), int32_t(v[2])}, {int32_t(v[3]), int32_t(v[4]), int32_t(v[5])}};
}

std::string boxText(const vox::IndexBox& b) {
  return std::to_string(b.min.u) + "," + std::to_string(b.min.v) + "," + std::to_string(b.min.w) + "," +
         std::to_string(b.max.u) + "," + std::to_string(b.max.v) + "," + std::to_string(b.max.w);
}

}  // namespace

std::optional<vox::SceneRegion> regionRecord(const VoxelizeOptions& o, const vox::SceneHeader& header,
                                             const std::string& settings) {
  if (!o.isRegionBake()) return std::nullopt;
  vox::SceneRegion r;
  const vox::Dims d = header.dims;
  if (!o.region.empty()) {
    const vox::RegionSpec spec = vox::parseRegionSpec(o.region);
    r.index = spec.index;
    r.count = spec.count;
    r.box = vox::regionTile(d, spec.index, spec.count);
  } else {
    const vox::IndexBox b = parseRegionBox(o.regionBox);
    const uint32_t dv[3] = {d.x, d.y, d.z};
    const int32_t hi[3] = {b.max.u, b.max.v, b.max.w};
    for (int i = 0; i < 3; ++i)
      if (uint32_t(hi[i]) >= dv[i])
        throw vox::Error(vox::ErrorKind::Usage, "--region-box " + o.regionBox + " reaches past the world's dims " +
                                                    vox::toString(d) + "; keep each max below its axis's size");
    if (!vox::isRegionAligned(b, d)) {
      // The nearest aligned box that holds it: mins down, ends up to 32-voxel cells (or the domain's end).
      const int32_t lo[3] = {b.min.u, b.min.v, b.min.w};
      int32_t nlo[3], nhi[3];
      const int32_t a = int32_t(vox::kRegionAlignVoxels);
      for (int i = 0; i < 3; ++i) {
        nlo[i] = lo[i] / a * a;
        nhi[i] = std::min<int32_t>(int32_t(dv[i]) - 1, (hi[i] / a + 1) * a - 1);
      }
      const vox::IndexBox near{{nlo[0], nlo[1], nlo[2]}, {nhi[0], nhi[1], nhi[2]}};
      throw vox::Error(vox::ErrorKind::Usage, "--region-box " + o.regionBox +
                                                  " is not on the tiling's 32-voxel cells (each min a multiple of 32, "
                                                  "each max + 1 a multiple of 32 or the axis's size); the nearest "
                                                  "aligned box holding it is --region-box " + boxText(near));
    }
    r.index = 0;
    r.count = 1;
    r.box = b;
  }
  vox::SceneHeader world = header;
  world.region.reset();
  r.worldKey = vox::regionWorldKey(world, settings);
  return r;
}

std::string voxelSettingsText(const VoxelizeOptions& o, const std::vector<std::string>& filesRead) {
  // Every option that can change a voxel, in a fixed order; placement options
  // too (the header records their result, this records how it was asked).
  std::string t = "voxelize-1";
  auto add = [&t](const std::string& key, const std::string& value) { t += " " + key + "=" + value; };
  add("res", std::to_string(o.resolutionOrDefault()));
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", o.voxelSize);
  add("voxel-size", buf);
  add("pad", std::to_string(o.pad));
  add("bounds", o.bounds);
  add("grid-size", o.gridSize);
  add("extent", o.extent ? *o.extent : "-");
  add("grid", o.gridName);
  if (o.threshold) std::snprintf(buf, sizeof buf, "%.17g", *o.threshold);
  add("threshold", o.threshold ? std::string(buf) : "-");
  add("fill", nameOf(fillModeNames(), o.fill));
  add("solid-rule", nameOf(solidRuleNames(), o.solidRule));
  add("method", nameOf(methodNames(), o.method));
  add("drop-invalid", o.dropInvalid ? "1" : "0");
  add("ignore-missing-materials", o.ignoreMissingMaterials ? "1" : "0");
  add("classes", o.classes.empty() ? "-" : vox::sha256File(o.classes));
  for (const std::string& f : filesRead) {
    uint64_t bytes = 0;
    std::string digest;
    try {
      digest = vox::sha256File(f, &bytes);
    } catch (const vox::Error&) {
      digest = "unreadable";
    }
    add("file", digest);
  }
  return t;
}

PreparedMeshes prepareMeshes(const VoxelizeOptions& o, Run& run, vox::DeferredTextures* deferred) {
  PreparedMeshes p;
  for (const std::string& in : o.inputs) vox::requireRegularFile(in);  // before the hasher opens (and a FIFO blocks) it
  InputHasher hasher(o.inputs);
  readMeshes(o, run, p, deferred);
  run.phase("prepare");  // classes, placement, provenance hashes
  if (p.mesh.triangles.empty())
    throw vox::Error(vox::ErrorKind::BadInput, o.inputs[0] + (o.inputs.size() > 1 ? " (and the other inputs)" : "") +
                                                   ": no triangles; there is nothing to voxelize");
  vox::ClassMapping mapping = classMapping(o, run, p.mesh);
  p.triangleClass = vox::assignClasses(p.mesh, mapping);
  // A scene lists the classes it holds: leave out those no triangle uses.
  vox::remapTriangleClasses(p.triangleClass, vox::compactClassTable(mapping.table, vox::classesOfTriangles(p.triangleClass),
                                                                    classIdPolicy(o)));
  placeScene(o, p.mesh, p.header);
  p.header.classes = mapping.table;
  p.header.sources = hasher.sources();
  return p;
}

namespace {

/// A voxel size with three significant digits, rounded up (larger voxels: fewer of them).
std::string voxelSizeText(double size) {
  const double scale = std::pow(10.0, std::floor(std::log10(size)) - 2);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", std::ceil(size / scale - 1e-9) * scale);
  return buf;
}

}  // namespace

void checkMeshBakeMemory(const VoxelizeOptions& o, Run& run, const PreparedMeshes& p, bool openvdb,
                         const vox::DeferredTextures* deferred) {
  const uint64_t resident = vox::residentBytesNow();
  // The peak of reading the mesh, past by now: the file mapped while parsed and
  // the arrays grown by doubling, about 33 bytes a triangle above what stays
  // for a 1,000,000-triangle OBJ. Where it exceeds the bake's own peak it is
  // the run's (docs/reliability.md "Memory").
  const uint64_t readingPeak = vox::peakResidentBytesSoFar();
  // Textures read by rows after the geometry, `threads` images at a time.
  const uint64_t decoding = deferred && deferred->images() > 0 ? deferred->readingBytes(run.threads()) : 0;
  vox::VoxelizeSettings settings;
  settings.fill = o.fill;
  settings.solidRule = o.solidRule;
  settings.threads = run.threads();  // colour sums live per tile, `threads` tiles at a time
  vox::DeferredTextures none;  // as the bake will have a source: only its presence counts
  if (deferred && deferred->images() > 0) settings.textureRows = &none;
  const bool sdf = o.method == VoxelizeMethod::Sdf;
  // The winding rule's tables hold the distinct positions (an STL's soup
  // welded), counted once for every resolution the search below tries.
  const uint64_t welded = o.fill == vox::FillMode::Solid && o.solidRule == vox::SolidRule::Winding && !sdf
                              ? vox::distinctPositions(p.mesh)
                              : p.mesh.positions.size();
  auto bakeEstimateFor = [&](const vox::SceneHeader& header, uint64_t maxPieces) {
    // A region bake's footprint is its box's (surfaceFootprint clips to header.region).
    const vox::SurfaceFootprint f = vox::surfaceFootprint(p.mesh, p.triangleClass, header, maxPieces, run.threads());
    vox::MemoryEstimate e;
    e.add("resident before the bake", resident);
    if (decoding) e.add("texture rows being read", decoding);
    if (sdf) {
      // meshToVolume: a float distance and an int32 closest-triangle grid over a
      // band of 2 voxels each side, with its per-thread working grids (measured).
      e.add("OpenVDB distance field", f.surfaceVoxels * 200.0);
      // What stays with each worker whatever the surface: its malloc arena
      // and meshToVolume's thread-local state, about 12 MiB a thread and 5
      // MiB more (measured: the cube at 64..384 missed 13-14 MiB at
      // --threads 1 and 21-29 MiB at 2, docs/reliability.md "Memory").
      e.add("OpenVDB workers", (5.0 + 12.0 * double(run.threads())) * 1024 * 1024);
      e.add("scene grids", f.blocks * 3000.0 + (o.fill == vox::FillMode::Solid ? f.enclosedVoxels / 512 * 3000.0 : 0.0));
      return e;
    }
    const double interior = o.fill == vox::FillMode::Solid ? f.enclosedVoxels / 512 : 0.0;
    // The direct writer beside the blocks: its leaf lists and a batch of leaf
    // buffers per thread (a mask and the compressed values of a leaf, at most
    // 89 bytes and 4 a vote or 12 a colour).
    const double perLeaf = f.blocks > 0 ? f.surfaceVoxels / f.blocks : 0.0;
    const double writer =
        openvdb ? 0.0
                : vox::directWriteBytes(f.blocks + interior, f.blockClasses + interior, p.mesh.hasColor() ? f.blocks : 0.0,
                                        89 + perLeaf * (p.mesh.hasColor() ? 12 : 4), run.threads());
    for (vox::MemoryPart& part : vox::estimateMeshBake(f, p.mesh, settings, welded, writer).parts)
      e.parts.push_back(std::move(part));
    if (!openvdb) e.add("scene writer", writer);
    if (openvdb) {
      // The scene built from the blocks: bool leaves for occupancy and surface,
      // an int32 vote leaf per class (interior blocks too: their runs' class),
      // a Vec3s colour leaf. The interior's vote leaves were missing: the
      // cube's solid fill at 256 with --check, 72 MiB of grids for 27 estimated.
      e.add("scene grids", (f.blocks + interior) * 2 * 200 + (f.blockClasses + interior) * 2200 +
                               (p.mesh.hasColor() ? f.blocks * 6300 : 0.0));
      // --check of a surface: every voxel a triangle touches in a hash set
      // beside the scene: a 16-byte node and its malloc header, and while the
      // set rehashes its old and new buckets (8 and 16 bytes a voxel). Not
      // per-thread memory: the cube at 512 missed 53-64 MiB, the set's 55.
      if (o.check && o.fill == vox::FillMode::Surface) e.add("surface check's voxel set", f.surfaceVoxels * 56.0);
      // OpenVDB's writer and the check's own buffers: 4 MB, as the direct
      // writer's fixed part (measured, not located: without it the cube and
      // the bunny at 256 and fandisk filled at 256 came out 1.03-1.04).
      e.add("scene writer and check", 4e6);
    }
    return e;
  };
  auto estimateFor = [&](const vox::SceneHeader& header, uint64_t maxPieces) {
    vox::MemoryEstimate e = bakeEstimateFor(header, maxPieces);
    if (readingPeak > e.bytes()) e.add("reading the mesh (its peak, before the bake)", readingPeak - e.bytes());
    return e;
  };
  const vox::MemoryEstimate estimate = estimateFor(p.header, uint64_t(1) << 22);
  const vox::Dims d = p.header.dims;
  const std::string what = "a " + vox::toString(d) + " " + nameOf(fillModeNames(), o.fill) + " bake" +
                           (sdf ? " (--method sdf)" : "");
  std::string suggestion;
  if (!run.memoryLimit().unlimited() && estimate.bytes() > run.memoryLimit().bytes) {
    // The largest resolution whose estimate fits (coarser counting: a few ms each).
    auto headerAt = [&](uint64_t res) {
      VoxelizeOptions r = o;
      r.resolution = uint32_t(res);
      r.voxelSize = 0;
      vox::SceneHeader h = p.header;
      placeScene(r, p.mesh, h);
      if (h.region && !h.region->box.empty()) {
        // The same part of the world at the other resolution: --region's tile
        // of the new dims, or --region-box scaled with them.
        if (!o.region.empty()) {
          h.region->box = vox::regionTile(h.dims, h.region->index, h.region->count);
        } else {
          vox::IndexBox& b = h.region->box;
          const double s[3] = {double(h.dims.x) / d.x, double(h.dims.y) / d.y, double(h.dims.z) / d.z};
          int32_t* lo[3] = {&b.min.u, &b.min.v, &b.min.w};
          int32_t* hi[3] = {&b.max.u, &b.max.v, &b.max.w};
          const uint32_t dv[3] = {h.dims.x, h.dims.y, h.dims.z};
          for (int k = 0; k < 3; ++k) {
            *lo[k] = int32_t(std::floor(*lo[k] * s[k]));
            *hi[k] = std::min(int32_t(dv[k]) - 1, int32_t(std::ceil((*hi[k] + 1) * s[k])) - 1);
          }
        }
      }
      return h;
    };
    auto bytesAt = [&](uint64_t res) { return estimateFor(headerAt(res), uint64_t(1) << 18).bytes(); };
    const uint64_t limit = run.memoryLimit().bytes;
    const uint64_t hi = std::min<uint64_t>(4096, std::max<uint64_t>(1, d.maxAxis()));
    uint64_t best = vox::largestFitting(1, hi, vox::suggestionBudget(limit), bytesAt);
    // The search counts coarsely; the run at the suggested setting estimates
    // finely: step down until the fine estimate fits too.
    uint64_t fine = best ? estimateFor(headerAt(best), uint64_t(1) << 22).bytes() : 0;
    for (int i = 0; i < 20 && best > 1 && fine > vox::suggestionBudget(limit); ++i) {
      best = std::max<uint64_t>(1, best * 97 / 100);
      fine = estimateFor(headerAt(best), uint64_t(1) << 22).bytes();
    }
    if (best > 0 && fine <= limit) {
      suggestion = o.voxelSize > 0 ? "--voxel-size " + voxelSizeText(headerAt(best).voxelSize)
                                   : "--res " + std::to_string(best);
      suggestion += " would need about " + vox::formatBytes(fine);
    }
    if (suggestion.empty() && o.fill == vox::FillMode::Solid) suggestion = "--fill surface needs less";
  }
  run.checkMemory(estimate, what, suggestion);
}

vox::VoxelizeSettings voxelizeSettings(const VoxelizeOptions& o, const Run& run, ProgressBar& bar) {
  vox::VoxelizeSettings settings;
  settings.fill = o.fill;
  settings.solidRule = o.solidRule;
  settings.threads = run.threads();
  settings.progress = [&bar](double f) { bar.update(f); };
  // Classes whose triangles left no vote (outside --bounds, zero area) are left
  // out of the scene; the direct path does it on its blocks itself.
  settings.leaveOutClassesWithoutVotes = classIdPolicy(o);
  return settings;
}

int finishMeshBake(const VoxelizeOptions& o, Run& run, const PreparedMeshes& p, uint64_t occupied, uint64_t surface,
                   size_t classesPresent, const vox::DeferredTextures* deferred) {
  const vox::Dims d = p.header.dims;
  std::vector<std::string> warnings = p.warnings;
  // An empty scene is written (a later step may expect the file), but never
  // silently: a --bounds box beside the mesh is the usual cause. A region bake's
  // empty tile is normal.
  if (occupied == 0 && !p.header.region) {
    warnings.push_back(o.output + ": the scene is empty: no triangle touches its " + vox::toString(d) + " voxels" +
                       (o.bounds.empty() ? "" : "; --bounds " + o.bounds + " may miss the mesh"));
    run.note("warning: " + warnings.back());
  }
  run.counts() = {{"dims", {d.x, d.y, d.z}},      {"triangles", p.mesh.triangles.size()},
                  {"vertices", p.mesh.positions.size()}, {"input_bytes", p.bytesRead},
                  {"occupied_voxels", occupied}, {"surface_voxels", surface},
                  {"classes_present", classesPresent}, {"method", nameOf(methodNames(), o.method)},
                  {"fill", nameOf(fillModeNames(), o.fill)}, {"warnings", warnings}};
  if (o.fill == vox::FillMode::Solid) run.counts()["solid_rule"] = nameOf(solidRuleNames(), o.solidRule);
  if (deferred && deferred->decodedImages() > 0)  // decoded during the voxelize phase, not the parse
    run.counts()["texture_decode"] = {{"images", deferred->decodedImages()},
                                      {"decode_seconds", deferred->decodeSeconds()}};
  if (p.header.region) {
    const vox::IndexBox& b = p.header.region->box;
    run.counts()["region"] = {{"index", p.header.region->index}, {"count", p.header.region->count},
                              {"box", b.empty() ? nlohmann::json(nullptr)
                                                : nlohmann::json{b.min.u, b.min.v, b.min.w, b.max.u, b.max.v, b.max.w}}};
  }
  run.noteWhenDone("wrote " + o.output + ": " + vox::toString(d) + ", " + counted(occupied, "occupied voxel", "occupied voxels") +
           " from " + counted(p.mesh.triangles.size(), "triangle", "triangles"));
  return run.finish();
}

int runMeshesDirect(const VoxelizeOptions& o, Run& run, const std::string& outputTemp) {
  // A glTF's colour textures are read by rows after the geometry, so no image
  // is held whole (formats/mesh/deferred_textures.h).
  vox::DeferredTextures textures;
  PreparedMeshes p = prepareMeshes(o, run, &textures);
  std::optional<vox::SceneRegion> region;
  if (o.isRegionBake()) {
    // The whole bake's class table, without the other regions: the classes
    // with a triangle touching the domain are exactly those the whole bake
    // keeps (leaveOutClassesWithoutVotes below, on the whole world's blocks).
    const std::array<bool, 256> used = vox::classesTouchingDomain(p.mesh, p.triangleClass, p.header);
    if (o.fill == vox::FillMode::Solid)
      for (const vox::ClassInfo& c : p.header.classes.classes())
        if (!used[c.id])
          throw vox::Error(vox::ErrorKind::Usage,
                           "--region with --fill solid: every triangle of class '" + c.name +
                               "' lies outside the grid (--bounds), so whether the whole bake keeps the class "
                               "depends on its interior; bake without --region, or widen --bounds");
    // A class none of whose triangles touches the domain (all of them outside
    // --bounds) is left out with its triangles: they vote in no voxel.
    if (std::any_of(p.triangleClass.begin(), p.triangleClass.end(), [&](uint8_t c) { return c != 0 && !used[c]; })) {
      std::vector<bool> keep(p.triangleClass.size());
      for (size_t t = 0; t < keep.size(); ++t) keep[t] = p.triangleClass[t] == 0 || used[p.triangleClass[t]];
      p.mesh.keepTriangles(keep, &p.triangleClass);
    }
    vox::remapTriangleClasses(p.triangleClass, vox::compactClassTable(p.header.classes, used, classIdPolicy(o)));
    region = regionRecord(o, p.header, voxelSettingsText(o, p.filesRead));
    p.header.region = region;
  }
  checkMeshBakeMemory(o, run, p, false, &textures);
  run.phase("voxelize");
  auto bar = run.progress("voxelize");
  vox::VoxelizeSettings settings = voxelizeSettings(o, run, *bar);
  if (region) settings.region = region->box;
  if (textures.images() > 0) settings.textureRows = &textures;
  vox::VoxelBlocks blocks;
  if (!region || !region->box.empty()) blocks = vox::voxelizeMeshBlocks(p.mesh, p.triangleClass, p.header, settings);
  textures.finish();  // a bake that never read them still fails on an undecodable image
  bar->done();
  for (const std::string& w : textures.warnings()) {  // as the read's warnings, found only now
    p.warnings.push_back(w);
    run.note("warning: " + w);
  }
  // Classes whose triangles left no vote (outside --bounds, zero area) are left
  // out too (a region's table was made the whole bake's above).
  if (!region) vox::leaveOutClassesWithoutVotes(blocks, p.header.classes, classIdPolicy(o));
  run.phase("write");
  const vox::DirectWriteSummary s = vox::writeSceneVdbDirect(p.header, blocks, outputTemp, run.threads());
  return finishMeshBake(o, run, p, s.occupied, s.surface, s.classesPresent.size(), &textures);
}

Command registerVoxelizeLight(CLI::App& root) {
  auto opts = std::make_shared<VoxelizeOptions>();
  CLI::App* cmd = addVoxelizeCommand(root, *opts);
  return {cmd, [opts]() -> int {
            if (!isLightBake(*opts)) return kDeferToFullModule;
            tuneAllocatorForShortRun();  // only once it is certain this process bakes
            checkVoxelizeOptions(*opts);
            Run run("voxelize", opts->common);
            const std::string outputTemp = run.output(opts->output);  // checks the destination before the work
            return runMeshesDirect(*opts, run, outputTemp);
          }};
}

}  // namespace voxcli
