// vox render-canonical: exact canonical-coordinate renders (DESIGN section 8).
// One ray per pixel centre into a scene or page file; every requested mode
// (canonical, class, shaded, depth, normal) comes from the same pass; the
// touched set of a camera path as JSON chunks and as a 2-bit atlas bitmap.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "formats/image/atlas_meta.h"
#include "formats/image/image.h"
#include "libvox/core/atlas_content.h"
#include "libvox/core/bitmap_packing.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"
#include "libvox/core/version.h"
#include "tools/cli/camera_options.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cmds/render_input.h"

namespace fs = std::filesystem;

namespace voxcli {

namespace {

const char* kModes[] = {"canonical", "class", "shaded", "depth", "normal"};

struct RenderCanonicalOptions {
  std::string input, output;
  std::string modes = "canonical";
  CameraOptions camera;
  std::string touched, touchedBitmap;
  uint32_t chunk = 16;
  bool check = false;
  double checkBudget = 2e9;
  int level = 0;
  int compression = 4;  // measured on a 1080p RGBA16 render: 2.7x faster than 6 for 25 % more bytes
  CommonOptions common;
};

uint64_t voxelKey(int32_t u, int32_t v, int32_t w) {
  return (uint64_t(uint32_t(w)) << 42) | (uint64_t(uint32_t(v)) << 21) | uint64_t(uint32_t(u));
}
vox::Coord3 keyVoxel(uint64_t k) {
  return {int32_t(k & 0x1fffff), int32_t((k >> 21) & 0x1fffff), int32_t(k >> 42)};
}

std::vector<std::string> parseModes(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string m = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (std::find(std::begin(kModes), std::end(kModes), m) == std::end(kModes))
      vox::throwUsage("--mode " + text + ": '" + m + "' is not one of canonical, class, shaded, depth, normal");
    if (std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// File of (view, mode): exactly -o for one view and one mode, else
// STEM[.viewN][.MODE].EXT with EXT what the mode's format needs.
std::string outputPath(const std::string& output, size_t view, size_t views, const std::string& mode, size_t modes,
                       const std::string& ext) {
  const fs::path p(output);
  const std::string given = lower(p.extension().string());
  if (views == 1 && modes == 1) {
    if (given != ext)
      vox::throwUsage("-o " + output + ": a " + mode + " render" +
                      (mode == "canonical" && ext == ".exr" ? " of this scene needs 32-bit samples, which PNG cannot hold," : "") +
                      " is written as " + ext + "; name the file *" + ext);
    return output;
  }
  fs::path stem = (given == ".png" || given == ".exr") ? p.parent_path() / p.stem() : p;
  std::string name = stem.string();
  if (views > 1) name += ".view" + std::to_string(view);
  if (modes > 1) name += "." + mode;
  return name + ext;
}

nlohmann::json matrixJson(const vox::Mat4d& m) { return nlohmann::json(std::vector<double>(m.begin(), m.end())); }

int runRenderCanonical(const RenderCanonicalOptions& o) {
  Run run("render-canonical", o.common);
  const std::vector<std::string> modes = parseModes(o.modes);
  if (o.output.empty() && o.touched.empty() && o.touchedBitmap.empty())
    vox::throwUsage("nothing to write: give -o FILE (and/or --touched FILE.json, --touched-bitmap FILE.png)");
  if (o.chunk == 0 || (o.chunk & (o.chunk - 1)) != 0 || o.chunk > 1024)
    vox::throwUsage("--chunk-size " + std::to_string(o.chunk) + ": expected a power of two 1..1024 (page files use 8, 16 or 32)");
  const std::vector<vox::CameraView> views = resolveCameras(o.camera, 512, 512);
  for (const vox::CameraView& v : views) {
    const uint64_t pixels = uint64_t(v.camera.width) * v.camera.height;
    if (pixels > (uint64_t(1) << 28))
      vox::throwUsage(v.label + ": " + std::to_string(v.camera.width) + " x " + std::to_string(v.camera.height) +
                      " is " + std::to_string(pixels) + " pixels; at most 268435456 per view (each needs a 20-byte hit "
                      "record in memory): render tiles with narrower fields of view");
  }

  const bool needSummaries = std::find(modes.begin(), modes.end(), "class") != modes.end() ||
                             std::find(modes.begin(), modes.end(), "shaded") != modes.end();
  run.phase("load");
  run.input(o.input);
  const RenderInput in = loadRenderInput(o.input, o.level, needSummaries);
  const vox::RayGrid& grid = *in.grid;
  const int bits = vox::canonicalBits(in.dims);
  for (const vox::CameraView& v : views) {
    for (int a = 0; a < 3; ++a) {
      const double g = (v.camera.eye[size_t(a)] - in.frame.origin[size_t(a)]) / in.frame.voxelSize;
      if (!(std::fabs(g) < 1e12))
        vox::throwUsage(v.label + ": the eye is " + std::to_string(g) +
                        " voxels from the grid on one axis; rays are exact up to 1e12 voxels away");
    }
  }

  // Plan the outputs before casting, so a bad name fails fast.
  struct Planned {
    size_t view;
    std::string mode, path;
  };
  std::vector<Planned> planned;
  if (!o.output.empty())
    for (size_t v = 0; v < views.size(); ++v)
      for (const std::string& m : modes) {
        const std::string ext = (m == "depth" || (m == "canonical" && bits == 32)) ? ".exr" : ".png";
        planned.push_back({v, m, outputPath(o.output, v, views.size(), m, modes.size(), ext)});
      }

  run.phase("cast");
  std::vector<vox::ViewHits> hits;
  uint64_t rays = 0, hitCount = 0, steps = 0;
  const auto castStart = std::chrono::steady_clock::now();
  {
    auto progress = run.progress("render");
    for (size_t v = 0; v < views.size(); ++v) {
      hits.push_back(vox::castView(grid, in.frame, views[v].camera, run.threads(), [&](double f) {
        progress->update((double(v) + f) / double(views.size()));
      }));
      rays += uint64_t(hits.back().width) * hits.back().height;
      hitCount += hits.back().hitCount;
      steps += hits.back().steps;
    }
    progress->done();
  }
  const double castSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - castStart).count();

  // Voxels hit by any ray (sorted keys), for class/shaded lookups and the touched set.
  std::vector<uint64_t> hitKeys;
  std::vector<vox::SummaryTexel> hitSummaries;
  if (needSummaries || !o.touched.empty() || !o.touchedBitmap.empty()) {
    run.phase("touched");
    for (const vox::ViewHits& h : hits)
      for (const vox::PixelHit& p : h.pixels)
        if (p.hit) hitKeys.push_back(voxelKey(p.u, p.v, p.w));
    std::sort(hitKeys.begin(), hitKeys.end());
    hitKeys.erase(std::unique(hitKeys.begin(), hitKeys.end()), hitKeys.end());
    if (needSummaries) {
      std::vector<vox::Coord3> voxels(hitKeys.size());
      for (size_t i = 0; i < hitKeys.size(); ++i) voxels[i] = keyVoxel(hitKeys[i]);
      hitSummaries = in.summaries(voxels);
    }
  }
  auto summaryOf = [&](const vox::PixelHit& p) {
    const auto it = std::lower_bound(hitKeys.begin(), hitKeys.end(), voxelKey(p.u, p.v, p.w));
    return hitSummaries[size_t(it - hitKeys.begin())];
  };

  nlohmann::json checkJson;
  uint64_t differing = 0;
  if (o.check) {
    run.phase("check");
    std::vector<vox::Coord3> occupied;
    occupied.reserve(size_t(grid.occupiedCount()));
    grid.forEachOccupied([&](uint32_t u, uint32_t v, uint32_t w) { occupied.push_back({int32_t(u), int32_t(v), int32_t(w)}); });
    uint64_t checked = 0;
    nlohmann::json mismatches = nlohmann::json::array();
    for (size_t v = 0; v < views.size(); ++v) {
      const uint64_t pixels = uint64_t(hits[v].width) * hits[v].height;
      const double cost = double(pixels) * double(std::max<size_t>(1, occupied.size()));
      const uint64_t stride = std::max<uint64_t>(1, uint64_t(std::ceil(cost / std::max(1.0, o.checkBudget))));
      const vox::ViewCheck c = vox::checkView(hits[v], occupied, in.frame, views[v].camera, stride, run.threads());
      checked += c.pixelsChecked;
      differing += c.pixelsDiffering;
      for (const auto& m : c.first) {
        if (mismatches.size() >= 10) break;
        nlohmann::json j = {{"view", v}, {"pixel", {m.x, m.y}}};
        j["got"] = m.got.hit ? nlohmann::json{m.got.u, m.got.v, m.got.w} : nlohmann::json(nullptr);
        j["expected"] = m.expected.hit ? nlohmann::json{m.expected.voxel.u, m.expected.voxel.v, m.expected.voxel.w}
                                       : nlohmann::json(nullptr);
        mismatches.push_back(j);
      }
      if (stride > 1)
        run.note(views[v].label + ": checked every " + std::to_string(stride) + "th pixel against the brute force (" +
                 std::to_string(c.pixelsChecked) + " of " + std::to_string(pixels) + "; raise --check-budget for all)");
    }
    checkJson = {{"pixels_checked", checked}, {"pixels_differing", differing}, {"first_mismatches", mismatches},
                 {"reference", "brute force: every occupied voxel against every checked ray"}};
    if (differing)
      std::cerr << "vox render-canonical: " << differing << " of " << checked
                << " checked pixels differ from the brute-force reference; first: " << mismatches[0].dump() << "\n";
  }

  run.phase("write");
  for (const Planned& pl : planned) {
    const vox::ViewHits& h = hits[pl.view];
    const vox::Camera& cam = views[pl.view].camera;
    const uint32_t W = h.width, H = h.height;
    vox::Image img;
    bool exr = false;
    if (pl.mode == "canonical") {
      if (bits == 8) img = vox::Image(W, H, 4, vox::SampleType::U8);
      else if (bits == 16) img = vox::Image(W, H, 4, vox::SampleType::U16);
      else img = vox::Image(W, H, 4, vox::SampleType::U32), exr = true;
      for (size_t i = 0; i < h.pixels.size(); ++i) {
        const vox::PixelHit& p = h.pixels[i];
        if (!p.hit) continue;
        if (bits == 8) {
          uint8_t* px = img.pixels.data() + i * 4;
          px[0] = uint8_t(p.u), px[1] = uint8_t(p.v), px[2] = uint8_t(p.w), px[3] = 255;
        } else if (bits == 16) {
          uint16_t* px = reinterpret_cast<uint16_t*>(img.pixels.data()) + i * 4;
          px[0] = uint16_t(p.u), px[1] = uint16_t(p.v), px[2] = uint16_t(p.w), px[3] = 65535;
        } else {
          uint32_t* px = reinterpret_cast<uint32_t*>(img.pixels.data()) + i * 4;
          px[0] = uint32_t(p.u), px[1] = uint32_t(p.v), px[2] = uint32_t(p.w), px[3] = 0xffffffffu;
        }
      }
    } else if (pl.mode == "class") {
      img = vox::Image(W, H, 4, vox::SampleType::U8);
      for (size_t i = 0; i < h.pixels.size(); ++i) {
        const vox::PixelHit& p = h.pixels[i];
        if (!p.hit) continue;
        const vox::ClassInfo* info = in.classes.find(summaryOf(p).cls);
        const vox::Rgb8 c = info ? info->color : vox::Rgb8{128, 128, 128};
        uint8_t* px = img.pixels.data() + i * 4;
        px[0] = c.r, px[1] = c.g, px[2] = c.b, px[3] = 255;
      }
    } else if (pl.mode == "shaded") {
      img = vox::Image(W, H, 3, vox::SampleType::U8);
      auto toByte = [](double c) { return uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); };
      for (size_t i = 0; i < h.pixels.size(); ++i) {
        const vox::PixelHit& p = h.pixels[i];
        std::array<double, 3> c = vox::kSkyColor;
        if (p.hit) {
          vox::Vec3d o, d;
          cam.pixelRay(uint32_t(i % W), uint32_t(i / W), o, d);
          const std::array<int, 3> n = vox::hitNormal(p, d);
          c = vox::terrainShade(vox::facePaletteColor(in.classes.find(summaryOf(p).cls), n), n);
        }
        uint8_t* px = img.pixels.data() + i * 3;
        for (int k = 0; k < 3; ++k) px[k] = toByte(c[size_t(k)]);
      }
    } else if (pl.mode == "depth") {
      img = vox::Image(W, H, 1, vox::SampleType::F32);
      exr = true;
      float* px = reinterpret_cast<float*>(img.pixels.data());
      for (size_t i = 0; i < h.pixels.size(); ++i)
        px[i] = h.pixels[i].hit ? h.pixels[i].depth : std::numeric_limits<float>::infinity();
    } else {  // normal
      img = vox::Image(W, H, 4, vox::SampleType::U8);
      for (size_t i = 0; i < h.pixels.size(); ++i) {
        const vox::PixelHit& p = h.pixels[i];
        if (!p.hit) continue;
        vox::Vec3d o, d;
        cam.pixelRay(uint32_t(i % W), uint32_t(i / W), o, d);
        const std::array<int, 3> n = vox::hitNormal(p, d);
        uint8_t* px = img.pixels.data() + i * 4;
        for (int k = 0; k < 3; ++k) px[k] = uint8_t(n[size_t(k)] < 0 ? 0 : n[size_t(k)] > 0 ? 255 : 128);
        px[3] = 255;
      }
    }
    nlohmann::json meta = {{"mode", pl.mode},
                           {"scene", in.path},
                           {"dims", {in.dims.x, in.dims.y, in.dims.z}},
                           {"origin", in.frame.origin},
                           {"voxel_size", in.frame.voxelSize},
                           {"view", views[pl.view].index},
                           {"camera", {{"viewMatrix", matrixJson(cam.view)},
                                       {"projectionMatrix", matrixJson(cam.projection)},
                                       {"imageSize", {{"width", W}, {"height", H}}}}}};
    if (pl.mode == "canonical") meta["bits"] = bits;
    if (in.kind == "pages") meta["level"] = in.level;
    img.text = {{"vox:canonical", meta.dump()}, {"Software", vox::versionString()}};
    const std::string tmp = run.output(pl.path);
    if (exr) vox::writeExr(img, tmp, vox::ExrCompression::Zip);
    else vox::writePngParallel(img, tmp, o.compression, run.threads());
  }

  // The touched set: chunks of C^3 voxels with the count of distinct voxels hit.
  if (!o.touched.empty()) {
    std::vector<std::pair<uint64_t, std::array<uint32_t, 3>>> chunkOf;
    chunkOf.reserve(hitKeys.size());
    for (uint64_t k : hitKeys) {
      const vox::Coord3 c = keyVoxel(k);
      const std::array<uint32_t, 3> ch{uint32_t(c.u) / o.chunk, uint32_t(c.v) / o.chunk, uint32_t(c.w) / o.chunk};
      chunkOf.push_back({vox::mortonEncode(ch[0], ch[1], ch[2]), ch});
    }
    std::sort(chunkOf.begin(), chunkOf.end());
    nlohmann::json chunks = nlohmann::json::array();
    for (size_t i = 0; i < chunkOf.size();) {
      size_t j = i;
      while (j < chunkOf.size() && chunkOf[j].first == chunkOf[i].first) ++j;
      chunks.push_back({{"chunk", chunkOf[i].second}, {"morton", chunkOf[i].first}, {"voxels", j - i}});
      i = j;
    }
    nlohmann::json t = {{"format", "voxbake-touched"},
                        {"scene", in.path},
                        {"dims", {in.dims.x, in.dims.y, in.dims.z}},
                        {"chunk_size", o.chunk},
                        {"views", views.size()},
                        {"rays", rays},
                        {"hits", hitCount},
                        {"voxels_touched", hitKeys.size()},
                        {"chunks_touched", chunks.size()},
                        {"chunks", chunks}};
    vox::writeFileBytes(run.output(o.touched), t.dump(1) + "\n");
  }
  if (!o.touchedBitmap.empty()) {
    const vox::AtlasLayout L = vox::AtlasLayout::make(in.dims);
    vox::OccupancyBitmap bitmap(L, 2);
    grid.forEachOccupied([&](uint32_t u, uint32_t v, uint32_t w) { bitmap.setOccupied(L.toTexel(u, v, w)); });
    for (uint64_t k : hitKeys) {
      const vox::Coord3 c = keyVoxel(k);
      bitmap.setTouched(L.toTexel(uint32_t(c.u), uint32_t(c.v), uint32_t(c.w)));
    }
    const fs::path p(o.touchedBitmap);
    for (uint32_t layer = 0; layer < L.layers; ++layer) {
      const vox::AtlasImageInfo info{L, vox::AtlasContent::Occupancy2, "bitmap", layer, 0, in.path};
      vox::Image img(bitmap.rowBytes(), L.height, 1, vox::SampleType::U8);
      img.pixels = bitmap.layerBytes(layer);
      img.text = vox::atlasImageText(info);
      const std::string path =
          L.layers == 1 ? o.touchedBitmap
                        : ((p.parent_path() / p.stem()).string() + ".layer" + std::to_string(layer) + ".png");
      vox::writePng(img, run.output(path), o.compression);
    }
  }

  const double mrays = castSeconds > 0 ? double(rays) / castSeconds / 1e6 : 0;
  run.counts() = {{"views", views.size()},
                  {"rays", rays},
                  {"hits", hitCount},
                  {"occupied_voxels", grid.occupiedCount()},
                  {"ray_grid_bytes", grid.memoryBytes()},
                  {"mean_steps_per_ray", rays ? double(steps) / double(rays) : 0.0},
                  {"rays_per_second", castSeconds > 0 ? double(rays) / castSeconds : 0.0},
                  {"mrays_per_second", mrays},
                  {"cast_seconds", castSeconds},
                  {"read_seconds", in.readSeconds},
                  {"ray_grid_seconds", in.gridSeconds},
                  {"files", planned.size() + (o.touched.empty() ? 0 : 1)}};
  if (!hitKeys.empty()) run.counts()["voxels_touched"] = hitKeys.size();
  if (o.check) run.error() = checkJson;
  char line[160];
  std::snprintf(line, sizeof line, "%llu rays in %.3f s (%.1f Mrays/s, %.1f steps/ray), %llu hits",
                static_cast<unsigned long long>(rays), castSeconds, mrays, rays ? double(steps) / double(rays) : 0.0,
                static_cast<unsigned long long>(hitCount));
  run.note(line);
  if (o.check && !differing) run.note("check: every checked pixel equals the brute-force reference");
  return run.finish(differing ? kExitCheckFailed : kExitOk);
}

}  // namespace

Command registerRenderCanonical(CLI::App& root) {
  auto o = std::make_shared<RenderCanonicalOptions>();
  CLI::App* cmd = root.add_subcommand("render-canonical", "Exact canonical-coordinate renders (and class, shaded, depth, normal)");
  cmd->footer(
      "One ray per pixel centre; RGB = (u, v, w) of the first voxel entered, alpha = hit, in the narrowest exact\n"
      "format (RGBA8 PNG up to 255, RGBA16 PNG up to 65535, RGBA32UI EXR beyond). With several views or modes,\n"
      "files are STEM[.viewN][.MODE].png|exr. Exit 1 when --check finds a pixel that differs from the brute force.");
  cmd->add_option("input", o->input, "Scene (.vdb) or page file (.vpk)")->required();
  cmd->add_option("-o,--output", o->output, "Image to write (.png; .exr for depth and 32-bit canonical)");
  cmd->add_option("--mode", o->modes, "Comma list of canonical, class, shaded, depth, normal")->capture_default_str();
  addCameraOptions(*cmd, o->camera);
  cmd->add_option("--touched", o->touched, "Write the chunks (and voxel counts) hit by any ray, as JSON");
  cmd->add_option("--chunk-size", o->chunk, "Chunk side for --touched")->capture_default_str();
  cmd->add_option("--touched-bitmap", o->touchedBitmap, "Write the 2-bit occupied+touched atlas bitmap (.png)");
  cmd->add_flag("--check", o->check, "Compare pixels with a brute-force reference; report differences (exit 1)");
  cmd->add_option("--check-budget", o->checkBudget,
                  "Ray-voxel tests the check may spend per view; past it, every k-th pixel is checked")
      ->capture_default_str();
  cmd->add_option("--level", o->level, "Page files: the level to render")->capture_default_str();
  cmd->add_option("--compression", o->compression, "PNG zlib level 0-9")->check(CLI::Range(0, 9))->capture_default_str();
  addCommonOptions(*cmd, o->common);
  return {cmd, [o] { return runRenderCanonical(*o); }};
}

}  // namespace voxcli
