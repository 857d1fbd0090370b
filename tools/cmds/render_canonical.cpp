// vox render-canonical: exact canonical-coordinate renders
// (docs/render.md; the files are formats/image/RENDER.md). One ray per pixel
// centre into a scene or page file; every requested mode comes from the same
// cast; the touched set of a camera path as JSON chunks and as a 2-bit atlas
// bitmap. The pixels are libvox/render's; this file runs the passes and writes
// the files. Both command modules link it: vox-cmds.so with the OpenVDB scene
// reader (cmd_render_canonical.cpp), the light render module without
// (render_main.cpp).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "formats/image/atlas_meta.h"
#include "formats/image/image.h"
#include "formats/image/render_meta.h"
#include "formats/image/touched_json.h"
#include "formats/pagefile/pack_chunks.h"
#include "libvox/core/atlas_content.h"
#include "libvox/core/error.h"
#include "libvox/core/version.h"
#include "libvox/render/render_modes.h"
#include "libvox/render/touched_voxels.h"
#include "libvox/render/voxel_walk.h"
#include "tools/cli/alloc_tuning.h"
#include "tools/cli/camera_options.h"
#include "tools/cli/cli.h"
#include "tools/cli/number_checks.h"
#include "tools/cli/commands.h"
#include "tools/cli/comma_list.h"
#include "tools/cli/enum_option.h"
#include "tools/cmds/render_canonical.h"
#include "tools/cmds/render_input.h"

namespace fs = std::filesystem;

namespace voxcli {

namespace {

const EnumNames<CheckReference>& checkReferenceNames() {
  static const EnumNames<CheckReference> names{{"walk", CheckReference::Walk}, {"brute-force", CheckReference::BruteForce}};
  return names;
}

constexpr uint32_t kDefaultImageSide = 512;
constexpr uint64_t kMaxPixelsPerView = uint64_t(1) << 28;  // each needs a 20-byte hit record in memory

std::string renderModeList() {
  std::string list;
  for (vox::RenderMode m : vox::kRenderModes) list += (list.empty() ? "" : ", ") + std::string(vox::renderModeName(m));
  return list;
}

// The modes in the order given, each once.
std::vector<vox::RenderMode> distinctModes(const std::vector<vox::RenderMode>& given) {
  std::vector<vox::RenderMode> out;
  for (vox::RenderMode m : given)
    if (std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
  return out;
}

bool anyModeNeedsClasses(const std::vector<vox::RenderMode>& modes) {
  return std::any_of(modes.begin(), modes.end(), vox::modeNeedsClasses);
}

void checkOutputOptions(const RenderCanonicalOptions& o) {
  if (o.output.empty() && o.touched.empty() && o.touchedBitmap.empty())
    vox::throwUsage("nothing to write: give -o FILE (and/or --touched FILE.json, --touched-bitmap FILE.png)");
  if (o.chunk == 0 || (o.chunk & (o.chunk - 1)) != 0 || o.chunk > 1024)
    vox::throwUsage("--chunk-size " + std::to_string(o.chunk) + ": expected a power of two 1..1024 (page files use 8, 16 or 32)");
}

// Options that tune another option's work do nothing without it: refused
// before anything is read, naming what to add.
void checkOptionsTakeEffect(const RenderCanonicalOptions& o) {
  auto given = [&o](const char* option) { return o.app && o.app->get_option(option)->count() > 0; };
  for (const char* option : {"--check-reference", "--check-seconds", "--check-budget"})
    if (!o.check && given(option))
      vox::throwUsage(std::string(option) + " sets how --check compares pixels, and --check is not given: add --check, "
                                            "or drop " + option);
  if (given("--check-budget") && o.checkReference != CheckReference::BruteForce)
    vox::throwUsage("--check-budget limits the brute-force reference, and this check uses the voxel walk "
                    "(--check-reference walk, the default): add --check-reference brute-force, or drop --check-budget");
  if (given("--chunk-size") && o.touched.empty())
    vox::throwUsage("--chunk-size sets the chunks of --touched FILE.json (--touched-bitmap is per voxel), and "
                    "--touched is not given: add --touched FILE.json, or drop --chunk-size");
}

std::vector<vox::CameraView> makeCameras(const CameraOptions& options,
                                         const std::optional<vox::WorldBox>& framing = std::nullopt) {
  const std::vector<vox::CameraView> views = resolveCameras(options, kDefaultImageSide, kDefaultImageSide, framing);
  for (const vox::CameraView& v : views) {
    const uint64_t pixels = uint64_t(v.camera.width) * v.camera.height;
    if (pixels > kMaxPixelsPerView)
      vox::throwUsage(v.label + ": " + std::to_string(v.camera.width) + " x " + std::to_string(v.camera.height) +
                      " is " + std::to_string(pixels) + " pixels; at most " + std::to_string(kMaxPixelsPerView) +
                      " per view (each needs a 20-byte hit record in memory): render tiles with narrower fields of view");
  }
  return views;
}

// Rays are exact only while doubles resolve a voxel at the eye's distance.
void checkEyesNearGrid(const std::vector<vox::CameraView>& views, const vox::GridFrame& frame) {
  for (const vox::CameraView& v : views) {
    for (int a = 0; a < 3; ++a) {
      const double gridEye = (v.camera.eye[size_t(a)] - frame.origin[size_t(a)]) / frame.voxelSize;
      if (!(std::fabs(gridEye) < 1e12)) {
        char far[32];
        std::snprintf(far, sizeof far, "%.3g", std::fabs(gridEye));
        const std::string what = std::string(": the eye is ") + far +
                                 " voxels from the grid on one axis; rays are exact up to 1e12 voxels away: "
                                 "move the eye closer";
        // A camera file is input (exit 3, named by file and element); a
        // camera made from options is a usage error.
        if (!v.source.empty()) throw vox::Error(vox::ErrorKind::BadInput, v.source + what);
        vox::throwUsage(v.label + what);
      }
    }
  }
}

bool pngHolds(vox::PixelSample s) { return s == vox::PixelSample::U8 || s == vox::PixelSample::U16; }

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// File of (view, mode): exactly -o for one view and one mode, else
// STEM[.viewN][.MODE].EXT with EXT what the mode's samples need.
std::string outputPath(const std::string& output, size_t view, size_t views, vox::RenderMode mode, size_t modes,
                       vox::PixelSample sample, bool orbit) {
  const std::string ext = pngHolds(sample) ? ".png" : ".exr";
  const std::string modeName = vox::renderModeName(mode);
  const fs::path p(output);
  const std::string given = lower(p.extension().string());
  if (views == 1 && modes == 1 && !orbit) {
    if (given != ext)
      vox::throwUsage("-o " + output + ": a " + modeName + " render" +
                      (mode == vox::RenderMode::Canonical && ext == ".exr"
                           ? " of this scene needs 32-bit samples, which PNG cannot hold,"
                           : "") +
                      " is written as " + ext + "; name the file *" + ext);
    return output;
  }
  fs::path stem = (given == ".png" || given == ".exr") ? p.parent_path() / p.stem() : p;
  std::string name = stem.string();
  if (orbit) {
    char n[16];
    std::snprintf(n, sizeof n, "_%03zu", view);
    name += n;
  } else if (views > 1) {
    name += ".view" + std::to_string(view);
  }
  if (modes > 1) name += "." + modeName;
  return name + ext;
}

struct PlannedImage {
  size_t view;
  vox::RenderMode mode;
  std::string path;
};

// Every image to write, named before anything is cast so that a bad name fails fast.
std::vector<PlannedImage> planImages(const std::string& output, size_t views, const std::vector<vox::RenderMode>& modes,
                                     int canonicalBits, bool orbit) {
  std::vector<PlannedImage> planned;
  if (output.empty()) return planned;
  for (size_t v = 0; v < views; ++v)
    for (vox::RenderMode m : modes)
      planned.push_back({v, m, outputPath(output, v, views, m, modes.size(), vox::modeSample(m, canonicalBits), orbit)});
  return planned;
}

struct CastViews {
  std::vector<vox::ViewHits> hits;  // one per view
  uint64_t rays = 0, hitCount = 0, steps = 0;
  double seconds = 0;
};

CastViews castViews(Run& run, const RenderInput& in, const std::vector<vox::CameraView>& views) {
  CastViews cast;
  const auto start = std::chrono::steady_clock::now();
  {
    auto progress = run.progress("render");
    for (size_t v = 0; v < views.size(); ++v) {
      cast.hits.push_back(vox::castView(*in.grid, in.frame, views[v].camera, run.threads(), [&](double f) {
        progress->update((double(v) + f) / double(views.size()));
      }));
      cast.rays += uint64_t(cast.hits.back().width) * cast.hits.back().height;
      cast.hitCount += cast.hits.back().hitCount;
      cast.steps += cast.hits.back().steps;
    }
    progress->done();
  }
  cast.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cast;
}

struct CheckOutcome {
  nlohmann::json report;
  uint64_t differing = 0;
};

// The sampling stride that makes checking `pixels` pixels take about `seconds`,
// from the rate measured on a pilot sample of about `pilotRays` pixels (spread
// over the image). 1 (every pixel) when the estimate fits or seconds <= 0.
uint64_t strideForSeconds(const vox::ViewHits& hits, const vox::ReferenceCaster& reference,
                          const vox::GridFrame& frame, const vox::Camera& camera, unsigned threads, double seconds,
                          uint64_t pilotRays) {
  const uint64_t pixels = uint64_t(hits.width) * hits.height;
  if (!(seconds > 0)) return 1;
  const uint64_t pilotStride = std::max<uint64_t>(1, pixels / std::max<uint64_t>(1, pilotRays));
  const auto start = std::chrono::steady_clock::now();
  const vox::ViewCheck pilot = vox::checkView(hits, reference, frame, camera, pilotStride, threads);
  const double elapsed = std::max(1e-6, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  const double rate = double(pilot.pixelsChecked) / elapsed;  // pixels per second
  if (double(pixels) / rate <= seconds) return 1;
  return std::max<uint64_t>(1, uint64_t(std::ceil(double(pixels) / (rate * seconds))));
}

std::string percentText(double fraction) {
  char t[32];
  std::snprintf(t, sizeof t, fraction >= 0.01 ? "%.1f %%" : "%.3f %%", fraction * 100);
  return t;
}

// Every view against the reference (the voxel walk, or the brute force), on
// every pixel or on a sample sized by --check-seconds (and, for the brute force,
// --check-budget).
CheckOutcome checkRender(Run& run, const RenderCanonicalOptions& o, const RenderInput& in,
                         const std::vector<vox::CameraView>& views, const CastViews& cast) {
  const auto start = std::chrono::steady_clock::now();
  const bool brute = o.checkReference == CheckReference::BruteForce;
  std::vector<vox::Coord3> occupied;  // the brute force's voxel list
  std::optional<vox::VoxelWalk> walk;
  vox::ReferenceCaster reference;
  if (brute) {
    occupied = in.grid->occupiedVoxels();
    reference = [&occupied](const vox::Ray& r) { return vox::castRayBruteForce(occupied, r); };
  } else {
    walk.emplace(*in.grid);
    reference = [&walk](const vox::Ray& r) { return walk->cast(r); };
  }
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::string referenceName = brute ? "brute-force" : "voxel-walk";
  CheckOutcome out;
  uint64_t checked = 0, pixelsTotal = 0, largestStride = 1;
  nlohmann::json mismatches = nlohmann::json::array(), perView = nlohmann::json::array();
  auto progress = run.progress("check");
  // A pilot of the brute force costs rays x occupied voxels: keep it near 2e8 tests.
  const uint64_t pilotRays =
      brute ? std::clamp<uint64_t>(uint64_t(2e8 / double(std::max<size_t>(1, occupied.size()))), 8, 2048) : 2048;
  for (size_t v = 0; v < views.size(); ++v) {
    const vox::ViewHits& hits = cast.hits[v];
    const uint64_t pixels = uint64_t(hits.width) * hits.height;
    // What is left of --check-seconds after reading the occupancy and the views before, shared by the views left
    // (at least 5 % of it, so that a slow setup still leaves a sample).
    const double seconds = o.checkSeconds > 0 ? std::max(o.checkSeconds - elapsed(), 0.05 * o.checkSeconds) /
                                                    double(views.size() - v)
                                              : 0.0;
    uint64_t stride = strideForSeconds(hits, reference, in.frame, views[v].camera, run.threads(), seconds, pilotRays);
    if (brute) stride = std::max(stride, vox::checkStride(pixels, occupied.size(), o.checkBudget));
    const vox::ViewCheck c = vox::checkView(hits, reference, in.frame, views[v].camera, stride, run.threads(),
                                            [&](double f) { progress->update((double(v) + f) / double(views.size())); });
    checked += c.pixelsChecked;
    pixelsTotal += pixels;
    largestStride = std::max(largestStride, stride);
    out.differing += c.pixelsDiffering;
    perView.push_back({{"view", v}, {"pixels", pixels}, {"checked", c.pixelsChecked}, {"differing", c.pixelsDiffering},
                       {"sampled_one_in", stride}});
    for (const auto& m : c.first) {
      if (mismatches.size() >= 10) break;
      nlohmann::json j = {{"view", v}, {"pixel", {m.x, m.y}}};
      j["got"] = m.got.hit ? nlohmann::json{m.got.u, m.got.v, m.got.w} : nlohmann::json(nullptr);
      j["expected"] = m.expected.hit ? nlohmann::json{m.expected.voxel.u, m.expected.voxel.v, m.expected.voxel.w}
                                     : nlohmann::json(nullptr);
      mismatches.push_back(j);
    }
  }
  progress->done();
  const double seconds = elapsed();
  const double fraction = pixelsTotal ? double(checked) / double(pixelsTotal) : 1.0;
  const nlohmann::json summary = {{"reference", referenceName},
                                  {"pixels", pixelsTotal},
                                  {"checked", checked},
                                  {"differing", out.differing},
                                  {"fraction", fraction},
                                  {"sampled_one_in", largestStride},
                                  {"seconds", seconds},
                                  {"views", perView}};
  run.report()["check"] = summary;
  out.report = {{"pixels_checked", checked},
                {"pixels_differing", out.differing},
                {"fraction_checked", fraction},
                {"sampled_one_in", largestStride},
                {"first_mismatches", mismatches},
                {"reference", brute ? "brute force: every occupied voxel against every checked ray"
                                    : "voxel walk: Amanatides-Woo DDA through every voxel the ray crosses"}};
  char time[32];
  std::snprintf(time, sizeof time, "%.2f s", seconds);
  std::string verdict = "check: ";
  if (checked == pixelsTotal)
    verdict += "all " + std::to_string(pixelsTotal) + " pixels checked";
  else
    verdict += std::to_string(checked) + " of " + std::to_string(pixelsTotal) + " pixels checked (sampled 1 in " +
               std::to_string(largestStride) + ", " + percentText(fraction) + "; raise --check-seconds for all)";
  verdict += " against the " + referenceName + " reference in " + std::string(time) + ": " +
             (out.differing ? std::to_string(out.differing) + " differ; first: " + mismatches[0].dump()
                            : std::string("none differ"));
  if (out.differing) std::cerr << "vox render-canonical: " << verdict << "\n";
  else run.note(verdict);
  return out;
}

vox::Image toImage(vox::ModeImage&& pixels) {
  vox::Image img;
  img.width = pixels.width;
  img.height = pixels.height;
  img.channels = pixels.channels;
  switch (pixels.sample) {
    case vox::PixelSample::U8: img.type = vox::SampleType::U8; break;
    case vox::PixelSample::U16: img.type = vox::SampleType::U16; break;
    case vox::PixelSample::U32: img.type = vox::SampleType::U32; break;
    case vox::PixelSample::F32: img.type = vox::SampleType::F32; break;
  }
  img.pixels = std::move(pixels.pixels);
  return img;
}

vox::RenderMeta renderMeta(const RenderInput& in, const vox::CameraView& view, vox::RenderMode mode, int canonicalBits) {
  vox::RenderMeta meta;
  meta.mode = mode;
  meta.scene = in.path;
  meta.dims = in.dims;
  meta.origin = in.frame.origin;
  meta.voxelSize = in.frame.voxelSize;
  meta.view = view.index;
  meta.viewMatrix = view.camera.view;
  meta.projectionMatrix = view.camera.projection;
  meta.width = view.camera.width;
  meta.height = view.camera.height;
  if (mode == vox::RenderMode::Canonical) meta.bits = canonicalBits;
  if (in.kind == "pages") meta.level = in.level;
  if (view.lookAt && !view.lookAt->view.empty()) meta.lookAt = view.lookAt;  // a camera vox chose
  return meta;
}

void writeImages(Run& run, const RenderCanonicalOptions& o, const RenderInput& in,
                 const std::vector<vox::CameraView>& views, const CastViews& cast,
                 const std::vector<PlannedImage>& planned, int canonicalBits, const vox::HitSummaries& summaries,
                 const vox::HitColors& colors) {
  for (const PlannedImage& pl : planned) {
    const vox::CameraView& view = views[pl.view];
    const vox::ModeSources sources{&view.camera, canonicalBits, &in.classes, summaries, colors, o.shadeColor};
    vox::Image img = toImage(vox::renderModeImage(pl.mode, cast.hits[pl.view], sources));
    const bool exr = !pngHolds(vox::modeSample(pl.mode, canonicalBits));
    img.text = {{vox::kRenderMetaKey, vox::renderMetaJson(renderMeta(in, view, pl.mode, canonicalBits))},
                {"Software", vox::versionString()}};
    const std::string tmp = run.output(pl.path);
    if (exr) vox::writeExr(img, tmp, vox::ExrCompression::Zip);
    else vox::writePngParallel(img, tmp, o.compression, run.threads());
  }
}

void writeTouchedSet(Run& run, const std::string& path, const RenderInput& in, size_t views, const CastViews& cast,
                     const vox::TouchedVoxels& touched, uint32_t chunkSide) {
  vox::TouchedSet set;
  set.scene = in.path;
  set.dims = in.dims;
  set.chunkSide = chunkSide;
  set.views = views;
  set.rays = cast.rays;
  set.hits = cast.hitCount;
  set.voxelsTouched = touched.size();
  set.chunks = vox::touchedChunks(touched, chunkSide);
  vox::writeFileBytes(run.output(path), vox::touchedSetJson(set));
}

// One file per atlas layer (FILE.layerN.png when there are several, as build-atlas names them).
void writeTouchedBitmap(Run& run, const std::string& path, const RenderInput& in, const vox::TouchedVoxels& touched,
                        int compression) {
  const vox::AtlasLayout layout = vox::AtlasLayout::make(in.dims);
  vox::OccupancyBitmap bitmap = vox::touchedBitmap(*in.grid, touched, layout);
  const fs::path p(path);
  for (uint32_t layer = 0; layer < layout.layers; ++layer) {
    const vox::AtlasImageInfo info{layout, vox::AtlasContent::Occupancy2, "bitmap", layer, 0, in.path};
    vox::Image img(bitmap.rowBytes(), layout.height, 1, vox::SampleType::U8);
    img.pixels = bitmap.layerBytes(layer);
    img.text = vox::atlasImageText(info);
    const std::string layerPath =
        layout.layers == 1 ? path : ((p.parent_path() / p.stem()).string() + ".layer" + std::to_string(layer) + ".png");
    vox::writePng(img, run.output(layerPath), compression);
  }
}

void reportCounts(Run& run, const RenderInput& in, size_t views, const CastViews& cast, size_t files,
                  const vox::TouchedVoxels& touched) {
  const double mrays = cast.seconds > 0 ? double(cast.rays) / cast.seconds / 1e6 : 0;
  const double stepsPerRay = cast.rays ? double(cast.steps) / double(cast.rays) : 0.0;
  run.counts() = {{"views", views},
                  {"rays", cast.rays},
                  {"hits", cast.hitCount},
                  {"occupied_voxels", in.grid->occupiedCount()},
                  {"ray_grid_bytes", in.grid->memoryBytes()},
                  {"mean_steps_per_ray", stepsPerRay},
                  {"rays_per_second", cast.seconds > 0 ? double(cast.rays) / cast.seconds : 0.0},
                  {"mrays_per_second", mrays},
                  {"cast_seconds", cast.seconds},
                  {"read_seconds", in.readSeconds},
                  {"ray_grid_seconds", in.gridSeconds},
                  {"files", files}};
  if (!touched.empty()) run.counts()["voxels_touched"] = touched.size();
  char line[160];
  std::snprintf(line, sizeof line, "%llu rays in %.3f s (%.1f Mrays/s, %.1f steps/ray), %llu hits",
                static_cast<unsigned long long>(cast.rays), cast.seconds, mrays, stepsPerRay,
                static_cast<unsigned long long>(cast.hitCount));
  run.note(line);
}

// --camera-out writes look-at cameras: refused before anything is read or cast.
void checkCameraOut(const std::string& path, const std::vector<vox::CameraView>& views) {
  if (path.empty()) return;
  for (const vox::CameraView& v : views)
    if (!v.lookAt)
      vox::throwUsage("--camera-out " + path + ": " + v.label +
                      " is given by matrices (a metadata.json view); --camera-out writes look-at cameras only");
}

// --camera-out: the cameras in the camera-file form --camera reads.
void writeCameraFile(Run& run, const std::string& path, const std::vector<vox::CameraView>& views) {
  checkCameraOut(path, views);
  std::vector<vox::LookAtCamera> cameras;
  for (const vox::CameraView& v : views) cameras.push_back(*v.lookAt);
  vox::writeFileBytes(run.output(path), vox::lookAtCameraFileJson(cameras));
}

}  // namespace

std::vector<vox::RenderMode> renderModes(const RenderCanonicalOptions& o) {
  if (o.modeLists.empty()) return {vox::RenderMode::Canonical};
  std::vector<vox::RenderMode> given;
  for (const std::string& list : o.modeLists)
    for (const std::string& name : splitCommaList(list, "--mode", "a comma list of " + renderModeList())) {
      const std::optional<vox::RenderMode> mode = vox::renderModeNamed(name);
      if (!mode) vox::throwUsage("--mode " + list + ": '" + name + "' is not one of " + renderModeList());
      given.push_back(*mode);
    }
  return distinctModes(given);
}

int runRenderCanonical(const RenderCanonicalOptions& o, const RenderLoader& load) {
  const std::vector<vox::RenderMode> modes = renderModes(o);  // a usage error before the run starts
  Run run("render-canonical", o.common);
  checkOutputOptions(o);
  checkOptionsTakeEffect(o);
  o.camera.check();
  // Cameras vox frames wait for the scene's occupied box; the others are checked before anything is read.
  std::vector<vox::CameraView> views;
  if (!o.camera.needsFraming()) views = makeCameras(o.camera);
  else if (!o.camera.size.empty()) parseImageSize(o.camera.size);
  checkCameraOut(o.cameraOut, views);
  // The output names too, unless they wait for the scene: a lone canonical
  // image is PNG or EXR by the grid's size.
  const size_t viewCount = o.camera.needsFraming() ? std::max<size_t>(o.camera.orbit, 1) : views.size();
  const bool orbit = o.camera.orbit > 0;
  if (!(viewCount == 1 && modes.size() == 1 && modes[0] == vox::RenderMode::Canonical && !orbit))
    planImages(o.output, viewCount, modes, /*canonicalBits, unused here=*/8, orbit);
  const bool needClasses = anyModeNeedsClasses(modes);
  const bool needColors = std::any_of(modes.begin(), modes.end(),
                                      [&](vox::RenderMode m) { return vox::modeNeedsColors(m, o.shadeColor); });

  // Tens of MB of fresh heap (the hit records, the images, the PNG): in huge
  // pages rather than 4 KB faults. A deferred run is then read by vox-cmds.so
  // with the same tuning.
  tuneAllocatorForShortRun();
  run.phase("load");
  run.input(o.input);
  std::optional<RenderInput> loaded = load(o.input, o.level, needClasses);
  if (!loaded) return kDeferToFullModule;  // nothing written yet
  const RenderInput& in = *loaded;
  if (o.camera.needsFraming()) views = makeCameras(o.camera, in.occupiedWorldBox());
  const int canonicalBits = vox::canonicalBits(in.dims);
  checkEyesNearGrid(views, in.frame);
  const std::vector<PlannedImage> planned = planImages(o.output, views.size(), modes, canonicalBits, orbit);

  {
    // Every view's hit records live until the last image is written; the
    // images are made and encoded one at a time: the largest three times (the
    // image, the encoder's output, at most about as large, and the heap the
    // image before it left). Measured on a 64^3 scene: 4096^2 canonical RGBA8
    // peaked at 24 bytes per pixel, all six modes at 29, four orbit views of
    // 2048^2 at 21 (docs/reliability.md).
    auto imagesAt = [&](double scale) {
      double pixels = 0, largestImage = 0;
      for (const vox::CameraView& v : views) {
        const double p = double(v.camera.width) * v.camera.height * scale * scale;
        pixels += p;
        if (!planned.empty())
          for (vox::RenderMode m : modes) {
            const vox::PixelSample s = vox::modeSample(m, canonicalBits);
            const double sampleBytes = s == vox::PixelSample::U8 ? 1 : s == vox::PixelSample::U16 ? 2 : 4;
            largestImage = std::max(largestImage, p * vox::modeChannels(m) * sampleBytes);
          }
      }
      vox::MemoryEstimate e;
      e.add("hit records", pixels * double(sizeof(vox::PixelHit)));
      e.add("image and its encoding", 3 * largestImage);
      return e;
    };
    const vox::MemoryEstimate images = imagesAt(1);
    std::string suggestion;
    const vox::MemoryLimit& limit = run.memoryLimit();
    if (!limit.unlimited() && !views.empty()) {
      // The largest image size (the same aspect) that fits, when that is what is over.
      const double base = double(run.workMemoryBase(1.0));
      double lo = 0, hi = 1;
      auto fits = [&](double scale) { return base + double(imagesAt(scale).bytes()) <= double(limit.bytes); };
      if (!fits(1) && fits(1.0 / 64)) {
        for (int i = 0; i < 40; ++i) ((fits((lo + hi) / 2)) ? lo : hi) = (lo + hi) / 2;
        lo *= 0.97;  // room for what the next run has resident besides
        const vox::Camera& c = views.front().camera;
        const uint64_t w = std::max<uint64_t>(1, uint64_t(c.width * lo)), h = std::max<uint64_t>(1, uint64_t(c.height * lo));
        suggestion = "--size " + std::to_string(w) + "x" + std::to_string(h) +
                     (views.size() > 1 ? " (or fewer views)" : "") + " would fit";
      }
    }
    run.checkWorkMemory("rendering " + o.input, 1.0, images, suggestion);
  }
  // Said only once every check has passed: a refused run prints its error alone.
  if (o.camera.needsFraming()) {
    if (in.grid->occupiedCount() == 0)
      run.note("warning: " + o.input + " has no occupied voxel: the views frame its whole grid, and every ray misses");
    for (const vox::CameraView& v : views) run.note(v.label + ": " + lookAtFlags(*v.lookAt));
  }
  run.phase("cast");
  const CastViews cast = castViews(run, in, views);

  vox::TouchedVoxels touched;
  std::vector<vox::SummaryTexel> touchedSummaries;
  std::vector<vox::VoxelColor8> touchedColors;
  if (needClasses || !o.touched.empty() || !o.touchedBitmap.empty()) {
    run.phase("touched");
    touched = vox::TouchedVoxels(cast.hits);
    if (needClasses) touchedSummaries = in.summaries(touched.voxels());
    if (needColors && in.hasColor()) touchedColors = in.colors(touched.voxels());
  }

  CheckOutcome check;
  if (o.check) {
    run.phase("check");
    check = checkRender(run, o, in, views, cast);
  }

  run.phase("write");
  writeImages(run, o, in, views, cast, planned, canonicalBits, vox::HitSummaries{&touched, touchedSummaries},
              vox::HitColors{&touched, touchedColors});
  if (!o.touched.empty()) writeTouchedSet(run, o.touched, in, views.size(), cast, touched, o.chunk);
  if (!o.touchedBitmap.empty()) writeTouchedBitmap(run, o.touchedBitmap, in, touched, o.compression);
  if (!o.cameraOut.empty()) writeCameraFile(run, o.cameraOut, views);

  reportCounts(run, in, views.size(), cast, planned.size() + (o.touched.empty() ? 0 : 1), touched);
  if (o.check) run.error() = check.report;
  return run.finish(check.differing ? kExitCheckFailed : kExitOk);
}

CLI::App* addRenderCanonicalOptions(CLI::App& root, RenderCanonicalOptions& opts) {
  RenderCanonicalOptions* o = &opts;
  CLI::App* cmd = root.add_subcommand("render-canonical", "Exact canonical-coordinate renders (and class, color, shaded, depth, normal)");
  cmd->footer(
      "One ray per pixel centre; RGB = (u, v, w) of the first voxel entered, alpha = hit, in the narrowest exact\n"
      "format (RGBA8 PNG up to 255, RGBA16 PNG up to 65535, RGBA32UI EXR beyond). With several views or modes,\n"
      "files are STEM[.viewN][.MODE].png|exr (orbits: STEM_000[.MODE]...). --view NAME and --orbit frame the\n"
      "box of occupied voxels (docs/render.md). Exit 1 when --check finds a pixel that differs from its reference.");
  cmd->add_option("input", o->input, "Scene (.vdb) or page file (.vpk)")->required();
  cmd->add_option("-o,--output", o->output, "Image to write (.png; .exr for depth and 32-bit canonical)");
  // Split by splitCommaList (renderModes), not CLI11's delimiter: it dropped empty entries unannounced.
  cmd->add_option("--mode", o->modeLists, "Comma list of " + renderModeList() + "; repeatable")
      ->type_name("LIST")
      ->default_str(vox::renderModeName(vox::RenderMode::Canonical));
  addCameraOptions(*cmd, o->camera);
  cmd->add_option("--touched", o->touched, "Write the chunks (and voxel counts) hit by any ray, as JSON");
  cmd->add_option("--chunk-size", o->chunk, "Chunk side for --touched")->capture_default_str();
  cmd->add_option("--touched-bitmap", o->touchedBitmap, "Write the 2-bit occupied+touched atlas bitmap (.png)");
  addEnumOption(*cmd, "--shade-color", o->shadeColor,
                EnumNames<vox::ShadeColor>{{"class", vox::ShadeColor::Class}, {"voxel", vox::ShadeColor::Voxel}},
                "What shaded lights: the class palette, or the voxel's colour where it has one");
  cmd->add_option("--camera-out", o->cameraOut, "Write the cameras used as a camera file (.json) --camera reads");
  cmd->add_flag("--check", o->check,
                "Compare pixels with a reference caster; verdict on stderr, differences give exit 1");
  addEnumOption(*cmd, "--check-reference", o->checkReference, checkReferenceNames(),
                "The reference: a plain voxel-by-voxel DDA, or every voxel against every ray");
  cmd->add_option("--check-seconds", o->checkSeconds,
                  "About how long the check may take (a measured rate decides how many pixels: 1 in K); 0 = every pixel")
      ->check(NonNegativeOrInfinity)
      ->capture_default_str();
  cmd->add_option("--check-budget", o->checkBudget,
                  "brute-force: ray-voxel tests the check may spend per view; past it, 1 pixel in K is checked")
      ->check(FinitePositive)
      ->capture_default_str();
  cmd->add_option("--level", o->level, "Page files: the level to render")->capture_default_str();
  cmd->add_option("--compression", o->compression, "PNG zlib level 0-9")->check(CLI::Range(0, 9))->capture_default_str();
  addCommonOptions(*cmd, o->common);
  o->app = cmd;
  return cmd;
}

}  // namespace voxcli
