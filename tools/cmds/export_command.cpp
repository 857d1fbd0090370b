#include "tools/cmds/export_command.h"

#include <filesystem>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/export/gltf_writer.h"
#include "formats/export/magicavoxel_writer.h"
#include "formats/export/ply_writer.h"
#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_class_volume.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/core/color_quantize.h"
#include "libvox/core/error.h"
#include "libvox/core/memory_budget.h"
#include "libvox/core/version.h"
#include "libvox/core/voxel_colors.h"
#include "tools/cli/comma_list.h"
#include "tools/cli/enum_option.h"

namespace voxcli {

namespace {

const EnumNames<ExportFormat>& formatNames() {
  static const EnumNames<ExportFormat> names{{"glb", ExportFormat::Glb},
                                             {"gltf", ExportFormat::Gltf},
                                             {"ply", ExportFormat::Ply},
                                             {"vox", ExportFormat::MagicaVoxel},
                                             {"vdb", ExportFormat::Vdb}};
  return names;
}

const EnumNames<vox::FaceColor>& colorNames() {
  static const EnumNames<vox::FaceColor> names{{"palette", vox::FaceColor::Palette}, {"voxel", vox::FaceColor::Voxel}};
  return names;
}

const EnumNames<ExportSplit>& splitNames() {
  static const EnumNames<ExportSplit> names{{"none", ExportSplit::None}, {"classes", ExportSplit::Classes}};
  return names;
}

bool isGltf(ExportFormat f) { return f == ExportFormat::Glb || f == ExportFormat::Gltf; }

/// "glTF (.glb)", for messages.
std::string formatText(ExportFormat f) {
  switch (f) {
    case ExportFormat::Glb: return "glTF (.glb)";
    case ExportFormat::Gltf: return "glTF (.gltf)";
    case ExportFormat::Ply: return "PLY (.ply)";
    case ExportFormat::MagicaVoxel: return "MagicaVoxel (.vox)";
    case ExportFormat::Vdb: return "OpenVDB (.vdb)";
    case ExportFormat::FromExtension: break;
  }
  return "no format";
}

/// Options that belong to some formats or modes are refused with any other
/// output (docs/export.md "Exit codes"): given, even at their default value,
/// they would be ignored without a word.
void checkOptionsFit(const ExportOptions& o, ExportFormat f) {
  auto given = [&](const char* name) { return o.app && o.app->count(name) > 0; };
  std::string what = formatText(f);  // and the mode, where options depend on it
  if (f == ExportFormat::Vdb && o.fog != o.levelSet)
    what = o.fog ? "an OpenVDB fog volume (.vdb --fog)" : "an OpenVDB level set (.vdb --level-set)";
  if (f == ExportFormat::MagicaVoxel && o.color == vox::FaceColor::Palette) what += " with the class palette";
  const std::string writes = "-o " + o.output + " writes " + what;
  auto refuse = [&](const std::string& option, const std::string& belongsTo, const std::string& fix = "") {
    vox::throwUsage(option + " is an option of " + belongsTo + ", but " + writes + ": " +
                    (fix.empty() ? "drop " + option : fix));
  };
  for (const char* name : {"--split", "--dedup", "--greedy"})
    if (given(name) && !isGltf(f)) refuse(name, "glTF block meshes (.glb, .gltf)");
  for (const char* name : {"--fog", "--level-set"})
    if (given(name) && f != ExportFormat::Vdb) refuse(name, "OpenVDB volumes (.vdb)");
  if (f == ExportFormat::Vdb) {
    if (o.fog && o.levelSet) vox::throwUsage("a .vdb export is one volume: give only one of --fog and --level-set");
    if (!o.fog && !o.levelSet) vox::throwUsage("a .vdb export is a fog volume or a level set: give --fog or --level-set");
    if (given("--color")) refuse("--color", "coloured exports (.glb, .gltf, .ply, .vox)");
  }
  if (given("--half-width") && !(f == ExportFormat::Vdb && o.levelSet))
    refuse("--half-width", "OpenVDB level sets (.vdb --level-set)");
  if (given("--quantize") && !(f == ExportFormat::MagicaVoxel && o.color == vox::FaceColor::Voxel))
    refuse("--quantize", "MagicaVoxel palettes of baked colours (.vox --color voxel)",
           f == ExportFormat::MagicaVoxel ? "add --color voxel for baked colours, or drop --quantize" : "");
  if (o.halfWidth < 1 || o.halfWidth > 64) vox::throwUsage("--half-width must be 1..64 voxels");
  if (o.level < 0) vox::throwUsage("--level must be >= 0");
}

std::optional<vox::IndexBox> parseRegion(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const std::string expected = "six integers umin,vmin,wmin,umax,vmax,wmax";
  std::vector<int64_t> v;
  for (const std::string& item : splitCommaList(text, "--region", expected)) {
    char* end = nullptr;
    const long long n = std::strtoll(item.c_str(), &end, 10);
    if (*end != '\0' || end == item.c_str() || n < INT32_MIN || n > INT32_MAX)
      vox::throwUsage("--region " + text + ": expected " + expected);
    v.push_back(n);
  }
  if (v.size() != 6) vox::throwUsage("--region " + text + ": expected six integers umin,vmin,wmin,umax,vmax,wmax");
  vox::IndexBox box{{int32_t(v[0]), int32_t(v[1]), int32_t(v[2])}, {int32_t(v[3]), int32_t(v[4]), int32_t(v[5])}};
  if (box.empty()) vox::throwUsage("--region " + text + ": each min must be <= its max (the box is inclusive)");
  return box;
}

/// Reads the input into `in`; false when the backend does not read it.
bool readInput(const ExportOptions& o, const std::optional<vox::IndexBox>& region, bool withColor,
               const ExportBackend& backend, Run& run, ExportInput& in) {
  run.input(o.input);
  run.checkOutputPath(o.output);  // before the read: exports register their files as they write them
  vox::requireRegularFile(o.input);
  if (vox::pagefile::looksLikePageFile(o.input)) {
    in.kind = "pages";
    const vox::pagefile::Reader reader = vox::pagefile::Reader::open(o.input);
    const vox::pagefile::Header& h = reader.header();
    if (o.level >= int(h.levelCount))
      throwLevelOutOfRange(o.level, o.input, h.levelCount);
    const auto d = h.levelDims(o.level);
    in.dims = {d[0], d[1], d[2]};
    in.frame.origin = h.origin;
    in.frame.voxelSize = h.voxelSize * double(uint64_t(1) << o.level);
    in.classes = vox::pagefile::readPageMeta(reader.metaJson(), o.input).classes;
    in.box = regionIn(region, in.dims, o.input);
    if (withColor && !(h.flags & vox::pagefile::kFlagColor))
      vox::throwBadInput(o.input + ": the page file has no baked colours; export the class palette (--color palette)");
    run.phase("volume");
    in.volume.emplace(vox::classVolumeFromPages(reader, o.level, in.box, in.classes, withColor, run.threads()));
    return true;
  }
  if (!vox::looksLikeVdb(o.input))
    vox::throwBadInput(o.input + ": not a scene: expected " + vox::describe(vox::FileKind::Vdb) + " or " +
                       vox::describe(vox::FileKind::PageFile));
  return backend.readVdb(o, region, withColor, run, in);
}

std::string stemOf(const std::string& path) { return std::filesystem::path(path).stem().string(); }

/// Meshes the blocks (culled, then merged with --greedy) and writes glTF.
void exportGltf(const ExportOptions& o, ExportFormat format, const ExportInput& in, Run& run) {
  run.phase("mesh");
  vox::BlockMeshSettings ms;
  ms.color = o.color;
  ms.threads = run.threads();
  ms.beforeAllocating = [&](uint64_t quads) {
    // The quads, counted exactly, and the writer's batches. --greedy holds,
    // per culled quad at most, the quad and either its copy in plane order or
    // the joined merged quads, plus the merged quads of the planes (up to
    // twice their count while they grow; mergeCoplanarFaces); --split one
    // copy by class.
    const double quad = double(sizeof(vox::BlockQuad));
    const double perQuad = o.greedy ? 4 * quad : (o.split == ExportSplit::Classes ? 2 : 1) * quad;
    vox::MemoryEstimate e;
    e.add("resident before meshing", vox::residentBytesNow());
    e.add("faces", double(quads) * perQuad);
    e.add("writer batches", vox::gltfWriteBufferBytes(o.dedup));
    run.checkMemory(e, "meshing the " + std::to_string(quads) + " visible faces of " + o.input);
  };
  vox::BlockMesh mesh = vox::meshVisibleFaces(*in.volume, in.classes, ms);
  const uint64_t culledQuads = mesh.quads.size();
  if (o.greedy) {
    run.phase("merge");
    mesh = vox::mergeCoplanarFaces(mesh, run.threads());
  }
  run.phase("write");
  vox::GltfScene scene;
  scene.name = stemOf(o.input);
  scene.generator = "voxbake " + vox::versionString() + " vox export";
  scene.frame = in.frame;
  scene.indexed = o.dedup;
  scene.threads = run.threads();
  std::vector<std::vector<vox::BlockQuad>> groups;
  if (o.split == ExportSplit::Classes) {
    groups = vox::quadsByClass(mesh);
    for (const auto& g : groups) {
      const vox::ClassInfo* c = in.classes.find(g.front().classId);
      scene.materials.push_back({c->name, c->id});
      scene.primitives.push_back({g, scene.materials.size() - 1});
    }
  } else if (!mesh.quads.empty()) {
    scene.materials.push_back({"blocks", std::nullopt});
    scene.primitives.push_back({mesh.quads, 0});
  }
  vox::GltfWriteResult written;
  if (format == ExportFormat::Glb) {
    written = vox::writeGlb(scene, run.output(o.output));
  } else {
    const std::string bin = (std::filesystem::path(o.output).parent_path() / (stemOf(o.output) + ".bin")).string();
    const std::string json = run.output(o.output);
    written = vox::writeGltf(scene, json, mesh.quads.empty() ? "" : run.output(bin), stemOf(o.output) + ".bin");
  }
  nlohmann::json& c = run.counts();
  c["faces"] = mesh.unitFaces;
  c["quads"] = mesh.quads.size();
  c["triangles"] = written.triangles;
  c["vertices"] = written.vertices;
  c["indices"] = written.indices;
  c["primitives"] = scene.primitives.size();
  c["buffer_bytes"] = written.bufferBytes;
  c["bytes"] = written.fileBytes;
  if (o.dedup) {
    c["buffer_bytes_without_dedup"] = written.unindexedBufferBytes;
    c["dedup_size_cut"] = written.unindexedBufferBytes
                              ? 1.0 - double(written.bufferBytes) / double(written.unindexedBufferBytes)
                              : 0.0;
  }
  if (o.greedy) {
    c["culled_triangles"] = 2 * culledQuads;
    c["greedy_triangle_ratio"] = mesh.quads.empty() ? 1.0 : double(culledQuads) / double(mesh.quads.size());
  }
  if (ms.color == vox::FaceColor::Voxel) c["faces_without_voxel_colour"] = mesh.uncoloredFaces;
  // Faces, not voxels: a voxel without visible faces (a solid's interior) is not drawn.
  if (mesh.uncoloredFaces)
    run.note("warning: " + o.input + ": " +
             (mesh.uncoloredFaces == 1 ? "1 face of a voxel without a baked colour takes its"
                                       : counted(mesh.uncoloredFaces, "face", "faces") +
                                             " of voxels without a baked colour take their") +
             " class's palette colour");
  std::string what = counted(mesh.unitFaces, "face", "faces") + ", " + counted(written.triangles, "triangle", "triangles");
  if (o.greedy)
    what += " (" + std::to_string(2 * culledQuads) + " before merging, ratio " +
            std::to_string(c["greedy_triangle_ratio"].get<double>()).substr(0, 5) + ")";
  run.noteWhenDone("wrote " + o.output + ": " + what + ", " + std::to_string(written.fileBytes) + " bytes");
}

/// PLY and .vox write every voxel, interior ones too: their uncoloured voxels are counted.
void noteUncolored(const std::string& input, uint64_t voxels, Run& run) {
  run.counts()["voxels_without_colour"] = voxels;
  if (voxels)
    run.note("warning: " + input + ": " + counted(voxels, "voxel has", "voxels have") + " no baked colour; " +
             (voxels == 1 ? "it has its" : "they have their") + " class's display colour");
}

/// Voxel centres with colour and class, binary PLY.
void exportPly(const ExportOptions& o, const ExportInput& in, Run& run) {
  run.phase("write");
  const vox::PlyWriteResult r =
      vox::writeVoxelPly(*in.volume, in.classes, o.color, in.frame, run.output(o.output));
  run.counts()["points"] = r.points;
  run.counts()["bytes"] = r.bytes;
  if (o.color == vox::FaceColor::Voxel) noteUncolored(o.input, r.uncolored, run);
  run.noteWhenDone("wrote " + o.output + ": " + counted(r.points, "point", "points") + ", " + std::to_string(r.bytes) + " bytes");
}

/// MagicaVoxel models; the palette is the class table (index = class id) or
/// the voxels' colours, quantised to 255 with --quantize.
void exportMagicaVoxel(const ExportOptions& o, const ExportInput& in, Run& run) {
  run.phase("palette");
  std::array<vox::Rgb8, 255> palette{};
  std::function<uint8_t(const vox::ClassVolume::Brick&, int)> indexOf;
  vox::QuantizedPalette q;
  vox::VoxelColors colors(in.classes, vox::FaceColor::Voxel);  // for indexOf
  nlohmann::json& c = run.counts();
  if (o.color == vox::FaceColor::Palette) {
    std::array<bool, 256> known{};
    for (const vox::ClassInfo& k : in.classes.classes()) {
      palette[k.id - 1] = k.color;
      known[k.id] = true;
    }
    indexOf = [known](const vox::ClassVolume::Brick& b, int i) {
      const uint8_t cls = b.classes[size_t(i)];
      if (!known[cls]) vox::throwClassNotInTable(cls, b.at(i));
      return cls;
    };
    c["palette"] = "classes";
  } else {
    vox::ColorHistogram histogram;
    vox::VoxelColors voxelColors(in.classes, vox::FaceColor::Voxel);
    for (const vox::ClassVolume::Brick& b : in.volume->bricks())
      for (int i = 0; i < vox::ClassVolume::kBrickVoxels; ++i)
        if (b.classes[size_t(i)]) ++histogram[vox::packRgb(voxelColors(b, i))];
    noteUncolored(o.input, voxelColors.uncolored(), run);
    if (histogram.size() > palette.size() && !o.quantize)
      vox::throwBadInput(o.input + ": the voxels have " + std::to_string(histogram.size()) +
                         " distinct colours and a .vox palette holds 255; quantise them (--quantize) or export "
                         "the class palette (--color palette)");
    q = vox::quantizeColors(histogram, palette.size());
    for (size_t k = 0; k < q.colors.size(); ++k) palette[k] = q.colors[k];
    indexOf = [&q, &colors](const vox::ClassVolume::Brick& b, int i) {
      return uint8_t(1 + q.slotOf.at(vox::packRgb(colors(b, i))));
    };
    c["palette"] = "colours";
    c["distinct_colours"] = histogram.size();
    c["palette_colours"] = q.colors.size();
    run.error()["quantization"] = {{"exact", q.exact},
                                   {"mean_srgb8_distance", q.meanError},
                                   {"max_srgb8_distance", q.maxError}};
    if (!q.exact)
      run.note("quantised " + counted(histogram.size(), "colour", "colours") + " to " + std::to_string(q.colors.size()) +
               ": mean error " + std::to_string(q.meanError) + ", max " + std::to_string(q.maxError) +
               " (8-bit sRGB units)");
  }
  run.phase("write");
  // Before the models are allocated or anything is written: the format's
  // size limit, then memory (4 bytes per voxel and a little per model).
  auto check = [&](const vox::MagicaVoxelPlan& plan) {
    if (plan.fileBytes - 20 > vox::kMagicaVoxelMaxChunkBytes)
      vox::throwBadInput(o.input + ": " + counted(plan.voxels, "voxel", "voxels") + " in " +
                         counted(plan.models, "model", "models") + " make a MagicaVoxel file of " +
                         std::to_string(plan.fileBytes) + " bytes, and a .vox file's chunks hold at most " +
                         std::to_string(vox::kMagicaVoxelMaxChunkBytes) +
                         " bytes (about 536 million voxels): export a part with --region" +
                         (in.kind == "scene" ? "" : ", or a coarser --level"));
    vox::MemoryEstimate e;
    e.add("resident before the models", vox::residentBytesNow());
    e.add("MagicaVoxel models", double(plan.memoryBytes));
    run.checkMemory(e, "the " + counted(plan.models, "MagicaVoxel model", "MagicaVoxel models") + " of " + o.input);
  };
  const vox::MagicaVoxelResult r = vox::writeMagicaVoxel(*in.volume, palette, indexOf, run.output(o.output), check);
  c["models"] = r.models;
  c["points"] = r.voxels;
  c["size"] = r.size;
  c["bytes"] = r.bytes;
  run.noteWhenDone("wrote " + o.output + ": " + counted(r.voxels, "voxel", "voxels") + " in " + counted(r.models, "model", "models") +
           ", " + std::to_string(r.bytes) + " bytes");
}

}  // namespace

nlohmann::json boxJson(const vox::IndexBox& b) {
  return {{"min", {b.min.u, b.min.v, b.min.w}}, {"max", {b.max.u, b.max.v, b.max.w}}};
}

/// --format, or the output's extension (".glb" for glb, and so on). --format
/// is for names without a known extension (out.bin); with one, it must agree.
ExportFormat outputFormat(const ExportOptions& o) {
  std::optional<std::pair<std::string, ExportFormat>> byExtension;
  for (const auto& [name, format] : formatNames())
    if (vox::hasExtension(o.output, "." + name)) byExtension.emplace(name, format);
  if (o.format == ExportFormat::FromExtension) {
    if (byExtension) return byExtension->second;
    vox::throwUsage("-o " + o.output + ": cannot tell the format from the extension; name it .glb .gltf .ply .vox .vdb"
                    " or give --format");
  }
  if (byExtension && byExtension->second != o.format) {
    const std::string named = nameOf(formatNames(), o.format);
    vox::throwUsage("--format " + named + " contradicts -o " + o.output + ", a ." + byExtension->first +
                    " name: name the output ." + named + " or drop --format");
  }
  return o.format;
}

void checkVolumeMemory(Run& run, const std::string& input, uint64_t bricks, bool withColor) {
  vox::MemoryEstimate e;
  e.add("resident after reading", vox::residentBytesNow());
  e.add("the volume", vox::ClassVolume::bytesFor(bricks, withColor));
  run.checkMemory(e, "the volume of " + input);
}

vox::IndexBox regionIn(const std::optional<vox::IndexBox>& region, const vox::Dims& dims, const std::string& path) {
  const vox::IndexBox domain = vox::domainBox(dims);
  if (!region) return domain;
  const vox::IndexBox& r = *region;
  if (r.min.u < 0 || r.min.v < 0 || r.min.w < 0 || r.max.u > domain.max.u || r.max.v > domain.max.v ||
      r.max.w > domain.max.w)
    vox::throwBadInput(path + ": the region " + vox::toString(r.min) + " .. " + vox::toString(r.max) +
                       " is not inside the scene's index box (0, 0, 0) .. " + vox::toString(domain.max));
  return r;
}

std::optional<int> runExport(const ExportOptions& o, const ExportBackend& backend) {
  const ExportFormat format = outputFormat(o);
  checkOptionsFit(o, format);
  const std::optional<vox::IndexBox> region = parseRegion(o.region);
  if (format == ExportFormat::Vdb && !backend.writeVdbVolume) return std::nullopt;
  if (backend.starting) backend.starting();
  Run run("export", o.common);
  run.phase("read");
  ExportInput in;
  if (!readInput(o, region, o.color == vox::FaceColor::Voxel, backend, run, in)) return std::nullopt;
  // glTF meshes are checked on their exact face count (exportGltf) and .vdb
  // volumes on the leaves their float grid spans (exportVdbVolume); PLY and
  // MagicaVoxel files are written as the volume is walked.
  if (!isGltf(format) && format != ExportFormat::Vdb) run.checkWorkMemory("exporting " + o.input, 1.0);
  nlohmann::json& c = run.counts();
  c["input_kind"] = in.kind;
  c["level"] = o.level;
  c["dims"] = {in.dims.x, in.dims.y, in.dims.z};
  c["region"] = boxJson(in.box);
  c["voxel_size"] = in.frame.voxelSize;
  c["voxels"] = in.volume->occupiedCount();
  if (in.volume->occupiedCount() == 0)
    run.note("warning: " + o.input + ": no occupied voxel in the region; writing an empty file");
  switch (format) {
    case ExportFormat::Glb:
    case ExportFormat::Gltf: exportGltf(o, format, in, run); break;
    case ExportFormat::Ply: exportPly(o, in, run); break;
    case ExportFormat::MagicaVoxel: exportMagicaVoxel(o, in, run); break;
    case ExportFormat::Vdb: backend.writeVdbVolume(o, in, run); break;
    case ExportFormat::FromExtension: throw vox::Error(vox::ErrorKind::Internal, "export: no format chosen");
  }
  return run.finish();
}

CLI::App* addExportOptions(CLI::App& root, ExportOptions& opts) {
  CLI::App* cmd = root.add_subcommand("export", "Write a scene as files other tools open (glTF, PLY, MagicaVoxel, OpenVDB)");
  cmd->footer(
      "Formats (by the output's extension, or --format):\n"
      "  .glb .gltf  the visible block faces as the block renderer builds them: per face its corners in\n"
      "              drawing order, normal, texture coordinates and the class's top/bottom/side palette\n"
      "              colour (COLOR_0, linear RGB), at (index + corner) * voxel size + origin; faces\n"
      "              between two occupied voxels are culled. .gltf writes OUT.bin beside it.\n"
      "Input: a scene .vdb, a pyramid .vdb (--level N) or a page file .vpk (--level N); --region\n"
      "limits the export to an index box (outside it counts as empty). docs/export.md.\n"
      "Example: vox export hamlet.vdb -o hamlet.glb --split classes --report export.json");
  cmd->add_option("input", opts.input, "Scene or pyramid (.vdb), or page file (.vpk)")->required();
  cmd->add_option("-o,--output", opts.output, "Output file (.glb .gltf .ply .vox .vdb)")->required();
  addEnumOption(*cmd, "--format", opts.format, formatNames(), "Output format (default: from the extension)");
  cmd->add_option("--level", opts.level, "Pyramid or page file level (0 = full resolution)")->capture_default_str();
  cmd->add_option("--region", opts.region, "Index box umin,vmin,wmin,umax,vmax,wmax (inclusive), default: all");
  addEnumOption(*cmd, "--color", opts.color, colorNames(),
                "Colours: palette (the class's) or voxel (the baked colour)");
  addEnumOption(*cmd, "--split", opts.split, splitNames(),
                "glTF: none (one primitive) or classes (one primitive and material per class)");
  cmd->add_flag("--dedup", opts.dedup, "Indexed triangles: 4 vertices per face instead of 6");
  cmd->add_flag("--greedy", opts.greedy, "Merge coplanar faces of one class and colour into rectangles");
  cmd->add_flag("--fog", opts.fog, ".vdb: a fog volume, density 1 in occupied voxels");
  cmd->add_flag("--level-set", opts.levelSet, ".vdb: a narrow-band level set of the occupied voxels");
  cmd->add_option("--half-width", opts.halfWidth, ".vdb --level-set: band half width in voxels")
      ->capture_default_str();
  cmd->add_flag("--quantize", opts.quantize, ".vox --color voxel: quantise more than 255 colours (median cut)");
  addCommonOptions(*cmd, opts.common);
  opts.app = cmd;
  return cmd;
}

}  // namespace voxcli
