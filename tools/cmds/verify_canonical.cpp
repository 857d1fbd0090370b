// vox verify-bijection --canonical IMG --scene S [camera]: checks a canonical
// render (formats/image/RENDER.md) the way idiff checks an image. Every pixel
// must decode: a hit pixel (alpha at full scale) to an occupied voxel of the
// scene, a miss pixel to (0, 0, 0, 0). With a camera (the image's own `vox:canonical` camera, or
// --camera/--eye...), every pixel must also be the voxel the exact caster finds,
// the voxel a plain voxel walk finds (voxel_walk.h, an independent caster), and
// a sample of pixels (all of them within --check-budget) the voxel a
// brute-force ray finds. Reports counts and the first offenders with their
// coordinates and both values; exit 1 when anything differs.
#include <iostream>
#include <nlohmann/json.hpp>

#include "formats/core/json_text.h"
#include "formats/image/image.h"
#include "formats/image/render_meta.h"
#include "libvox/core/error.h"
#include "libvox/core/number_text.h"
#include "libvox/render/render.h"
#include "libvox/render/voxel_walk.h"
#include "tools/cmds/render_input.h"
#include "tools/cli/verify_bijection.h"

namespace voxcli {

namespace {

std::string voxelText(const vox::Coord3& c) { return vox::toString(c); }

}  // namespace

int runCanonicalCheck(const VerifyBijectionOptions& o) {
  Run run("verify-bijection", o.common);
  run.phase("read");
  run.input(o.canonical);
  vox::requireRegularFile(o.canonical);  // "no such file" rather than "not a PNG or EXR image"
  vox::Image img;
  if (vox::isPngFile(o.canonical)) img = vox::readPng(o.canonical);
  else if (vox::isExrFile(o.canonical)) img = vox::readExr(o.canonical);
  else vox::throwBadInput(o.canonical + ": not a PNG or EXR image");
  vox::requireCanonicalImage(img, o.canonical);
  const std::optional<vox::RenderMeta> meta = vox::readRenderMeta(img, o.canonical);
  const int level = meta && meta->level ? *meta->level : 0;
  run.input(o.scene);
  const RenderInput in = loadRenderInput(o.scene, level, /*needSummaries=*/false);
  if (meta && meta->dims != in.dims) {
    auto dimsText = [](const vox::Dims& d) { return nlohmann::json{d.x, d.y, d.z}.dump(); };
    vox::throwBadInput(o.canonical + ": rendered from a " + dimsText(meta->dims) + " grid, but " + o.scene + " is " +
                       dimsText(in.dims));
  }
  // A scene of the same dims placed elsewhere (another origin or voxel size)
  // would fail every ray; say why once instead.
  if (meta && (meta->origin != in.frame.origin || meta->voxelSize != in.frame.voxelSize)) {
    auto placement = [](const std::array<double, 3>& origin, double voxelSize) {
      return "origin " + nlohmann::json(origin).dump() + ", voxel size " + vox::shortestText(voxelSize);
    };
    vox::throwBadInput(o.canonical + ": rendered from a grid at " + placement(meta->origin, meta->voxelSize) + ", but " +
                       o.scene + " is at " + placement(in.frame.origin, in.frame.voxelSize) +
                       "; check it against the scene it was rendered from");
  }

  // The camera: given on the command line, else the image's own.
  std::optional<vox::Camera> camera;
  std::string cameraFrom;
  if (o.camera.given()) {
    std::vector<vox::CameraView> views = resolveCameras(
        o.camera, img.width, img.height,
        o.camera.needsFraming() ? std::optional<vox::WorldBox>(in.occupiedWorldBox()) : std::nullopt);
    if (views.size() != 1) {
      // A camera file with several views (--orbit N > 1 is refused before the reads).
      const std::string given = o.camera.cameraFile.empty() ? "--orbit " + std::to_string(o.camera.orbit) + " makes"
                                                             : "--camera " + o.camera.cameraFile + " holds";
      vox::throwUsage(given + " " + std::to_string(views.size()) + " views, but " + o.canonical +
                      " is one image; pick the one it was rendered from" +
                      (o.camera.cameraFile.empty() ? std::string() : " with --view INDEX"));
    }
    camera = views[0].camera;
    cameraFrom = "command line";
  } else if (meta) {
    camera = vox::renderCamera(*meta, img, o.canonical,
                               "check the image as rendered, or give the camera for this image with --camera FILE "
                               "or --eye/--target");
    cameraFrom = "image metadata";
  } else {
    // Without a camera only the decoding could be checked, not a single ray.
    vox::throwBadInput(o.canonical + ": has no render metadata (its text chunk was dropped, e.g. by an image "
                       "optimizer), so its rays cannot be checked; give the camera with --camera FILE or --eye/--target");
  }
  if (camera && (camera->width != img.width || camera->height != img.height))
    vox::throwUsage("the camera renders " + std::to_string(camera->width) + " x " + std::to_string(camera->height) +
                    " pixels but " + o.canonical + " is " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                    "; give --size " + std::to_string(img.width) + "x" + std::to_string(img.height));

  run.phase("decode");
  const uint64_t full = vox::canonicalFullScale(img);
  const size_t n = size_t(img.width) * img.height;
  struct Failure {
    uint32_t x, y;
    std::string what;
  };
  std::vector<Failure> failures;
  uint64_t failureCount = 0, hitPixels = 0, decodeFailures = 0;
  auto fail = [&](size_t i, std::string what) {
    ++failureCount;
    if (failures.size() < 10) failures.push_back({uint32_t(i % img.width), uint32_t(i / img.width), std::move(what)});
  };
  std::vector<vox::PixelHit> decoded(n);
  for (size_t i = 0; i < n; ++i) {
    const auto [r, g, b, a] = vox::canonicalSamples(img, i);
    if (a == 0) {
      if (r || g || b) {
        ++decodeFailures;
        fail(i, "miss pixel (alpha 0) with RGB (" + std::to_string(r) + ", " + std::to_string(g) + ", " + std::to_string(b) + ")");
      }
      continue;
    }
    if (a != full) {
      ++decodeFailures;
      fail(i, "alpha " + std::to_string(a) + " is neither 0 (miss) nor " + std::to_string(full) + " (hit)");
      continue;
    }
    ++hitPixels;
    const vox::Coord3 c{int32_t(r), int32_t(g), int32_t(b)};
    if (r >= in.dims.x || g >= in.dims.y || b >= in.dims.z) {
      ++decodeFailures;
      fail(i, "decodes to voxel (" + std::to_string(r) + ", " + std::to_string(g) + ", " + std::to_string(b) +
                  "), outside the " + vox::toString(in.dims) + " grid");
      continue;
    }
    if (!in.grid->occupied(c.u, c.v, c.w)) {
      ++decodeFailures;
      fail(i, "decodes to voxel " + voxelText(c) + ", which is empty in " + o.scene);
      continue;
    }
    decoded[i] = {c.u, c.v, c.w, 0, -1, 0, true};
  }

  uint64_t castDiffer = 0, walkDiffer = 0, bruteChecked = 0, bruteDiffer = 0, bruteStride = 1;
  if (camera) {
    run.phase("cast");
    const vox::ViewHits ours = vox::castView(*in.grid, in.frame, *camera, run.threads());
    for (size_t i = 0; i < n; ++i) {
      const vox::PixelHit& p = ours.pixels[i];
      const vox::PixelHit& d = decoded[i];
      const bool same = p.hit == d.hit && (!p.hit || (p.u == d.u && p.v == d.v && p.w == d.w));
      if (same) continue;
      ++castDiffer;
      fail(i, std::string("image has ") + (d.hit ? voxelText({d.u, d.v, d.w}) : "a miss") + ", the ray hits " +
                  (p.hit ? voxelText({p.u, p.v, p.w}) : "nothing"));
    }
    const std::vector<vox::Coord3> occupied = in.grid->occupiedVoxels();
    vox::ViewHits image;
    image.width = img.width;
    image.height = img.height;
    image.pixels = decoded;
    // Every pixel against the plain voxel walk, which shares no code with the caster above.
    run.phase("voxel walk");
    const vox::VoxelWalk walk(occupied);
    const vox::ViewCheck wc = vox::checkView(
        image, [&walk](const vox::Ray& r) { return walk.cast(r); }, in.frame, *camera, 1, run.threads());
    walkDiffer = wc.pixelsDiffering;
    for (const auto& m : wc.first) {
      if (failures.size() >= 10) break;
      failures.push_back({m.x, m.y,
                          std::string("image has ") + (m.got.hit ? voxelText({m.got.u, m.got.v, m.got.w}) : "a miss") +
                              ", the voxel-walk ray hits " + (m.expected.hit ? voxelText(m.expected.voxel) : "nothing")});
    }
    run.phase("brute force");
    const uint64_t stride = vox::checkStride(n, occupied.size(), o.checkBudget);
    bruteStride = stride;
    const vox::ViewCheck c = vox::checkView(image, occupied, in.frame, *camera, stride, run.threads());
    bruteChecked = c.pixelsChecked;
    bruteDiffer = c.pixelsDiffering;
    for (const auto& m : c.first) {
      if (failures.size() >= 10) break;
      failures.push_back({m.x, m.y,
                          std::string("image has ") + (m.got.hit ? voxelText({m.got.u, m.got.v, m.got.w}) : "a miss") +
                              ", the brute-force ray hits " + (m.expected.hit ? voxelText(m.expected.voxel) : "nothing")});
    }
  }

  const bool ok = decodeFailures == 0 && castDiffer == 0 && walkDiffer == 0 && bruteDiffer == 0;
  nlohmann::json j = {{"image", o.canonical},
                      {"scene", o.scene},
                      {"pixels", n},
                      {"hit_pixels", hitPixels},
                      {"decode_failures", decodeFailures},
                      {"camera", camera ? nlohmann::json(cameraFrom) : nlohmann::json(nullptr)},
                      {"ok", ok}};
  if (camera) {
    j["pixels_differing_from_ray"] = castDiffer;
    j["pixels_differing_from_voxel_walk"] = walkDiffer;
    j["brute_force_pixels_checked"] = bruteChecked;
    j["brute_force_pixels_differing"] = bruteDiffer;
    j["brute_force_sampled_one_in"] = bruteStride;
    j["brute_force_fraction_checked"] = n ? double(bruteChecked) / double(n) : 1.0;
  }
  nlohmann::json fj = nlohmann::json::array();
  for (const Failure& f : failures) fj.push_back({{"pixel", {f.x, f.y}}, {"what", f.what}});
  j["first_failures"] = fj;
  run.counts() = {{"pixels", n}, {"hit_pixels", hitPixels}};
  run.error() = j;
  if (o.json) {
    std::cout << vox::jsonText(j, 2) << "\n";
  } else {
    std::cout << o.canonical << ": " << counted(n, "pixel", "pixels") << ", " << counted(hitPixels, "hit", "hits") << "; "
              << decodeFailures << (decodeFailures == 1 ? " does" : " do") << " not decode to an occupied voxel of "
              << o.scene << "\n";
    if (camera)
      std::cout << "  camera from the " << cameraFrom << ": "
                << counted(castDiffer, "pixel differs", "pixels differ") << " from the exact ray, "
                << walkDiffer << " from the voxel-walk ray (every pixel), "
                << bruteDiffer << " of " << counted(bruteChecked, "pixel", "pixels")
                << " checked against the brute-force ray " << (bruteDiffer == 1 ? "differs" : "differ")
                << (bruteStride > 1 ? " (sampled 1 in " + std::to_string(bruteStride) + ")" : std::string(" (every pixel)"))
                << "\n";
    else
      std::cout << "  no camera (the image has none and none was given): decoding checked only\n";
    for (const Failure& f : failures) std::cout << "  pixel (" << f.x << ", " << f.y << "): " << f.what << "\n";
    std::cout << (ok ? "OK" : "FAILED") << "\n";
  }
  return run.finish(ok ? kExitOk : kExitCheckFailed);
}

}  // namespace voxcli
