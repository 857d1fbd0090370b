// vox verify-bijection: proves the atlas mapping for a layout (--dims/--res),
// measures what a texel format holds exactly (--format), and checks a built
// atlas against its scene (--atlas with --scene). The first two run in the
// launcher without OpenVDB (docs/startup.md); --atlas runs in the module.
#include "tools/cli/verify_bijection.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>
#include <sstream>
#include <thread>

#include "libvox/core/atlas_mapping.h"
#include "libvox/core/bijection_proof.h"
#include "libvox/core/error.h"
#include "libvox/core/texel_formats.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/number_checks.h"

namespace voxcli {

namespace {

std::string coord(const vox::Coord3& c) { return vox::toString(c); }
std::string texel(const vox::TexelAddress& t) {
  return "(layer " + std::to_string(t.layer) + ", x " + std::to_string(t.x) + ", y " + std::to_string(t.y) + ")";
}

nlohmann::json layoutJson(const vox::AtlasLayout& L) { return nlohmann::json::parse(L.toJson()); }

int runProof(const VerifyBijectionOptions& o, Run& run, std::ostream& out) {
  vox::Dims d;
  if (!o.dims.empty()) {
    const auto t = parseTriple(o.dims, "--dims");
    d = {t[0], t[1], t[2]};
  } else {
    d = {o.res, o.res, o.res};
  }
  run.phase("layout");
  const vox::AtlasLayout L = vox::AtlasLayout::make(d, o.tilesPerRow, o.maxSide);
  run.phase("prove");
  const auto t0 = std::chrono::steady_clock::now();
  const vox::BijectionResult r = vox::proveBijection(L, run.threads());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double pairsPerSecond = seconds > 0 ? double(r.voxelsChecked) / seconds : 0;
  nlohmann::json j = {{"dims", {d.x, d.y, d.z}},  {"layout", layoutJson(L)},        {"method", r.method},
                      {"voxels_checked", r.voxelsChecked}, {"texels_checked", r.texelsChecked},
                      {"padding_texels", r.paddingTexels}, {"failures", r.failures}, {"seconds", seconds},
                      {"pairs_per_second", pairsPerSecond}, {"threads", run.threads()}, {"ok", r.ok()}};
  if (!r.argument.empty()) j["argument"] = r.argument;
  if (r.first) {
    nlohmann::json f = {{"what", r.first->what},
                        {"voxel", {r.first->voxel.u, r.first->voxel.v, r.first->voxel.w}},
                        {"texel", {r.first->texel.layer, r.first->texel.x, r.first->texel.y}}};
    if (r.first->decoded) f["decoded"] = {r.first->decoded->u, r.first->decoded->v, r.first->decoded->w};
    j["first_failure"] = f;
  }
  run.counts() = {{"voxels_checked", r.voxelsChecked}, {"texels_checked", r.texelsChecked}, {"failures", r.failures}};
  run.error() = {{"failures", r.failures}, {"pairs_per_second", pairsPerSecond}};
  if (o.json) {
    out << j.dump(2) << "\n";
  } else {
    out << "bijection " << vox::toString(d) << " <-> " << L.width << " x " << L.height << " x " << L.layers
        << (L.layers == 1 ? " layer" : " layers") << " (tiles per row " << L.tilesPerRow << ", tile rows per layer "
        << L.rowsPerLayer << "): " << r.method << "\n";
    if (r.method == "exhaustive")
      out << "  " << counted(r.voxelsChecked, "voxel", "voxels") << ", " << counted(r.texelsChecked, "texel", "texels")
          << " (" << r.paddingTexels << " padding), " << counted(r.failures, "failure", "failures") << "\n";
    else
      out << "  " << counted(r.voxelsChecked, "axis position", "axis positions") << ", "
          << counted(r.texelsChecked, "tile slot", "tile slots") << " ("
          << counted(r.paddingTexels, "padding texel", "padding texels") << "), "
          << counted(r.failures, "failure", "failures") << "\n";
    char rate[96];
    std::snprintf(rate, sizeof rate, "  %.1f M %s/s on %s (%.3f s)\n", pairsPerSecond / 1e6,
                  r.method == "exhaustive" ? "pairs" : "checks", counted(run.threads(), "thread", "threads").c_str(),
                  seconds);
    out << rate;
    if (!r.argument.empty()) out << "  " << r.argument << "\n";
    if (r.first)
      out << "  first failure: " << r.first->what << ": voxel " << coord(r.first->voxel) << " -> texel "
          << texel(r.first->texel)
          << (r.first->decoded ? " -> voxel " + coord(*r.first->decoded) : std::string(" -> no voxel")) << "\n";
    out << (r.ok() ? "OK" : "FAILED") << "\n";
  }
  return r.ok() ? kExitOk : kExitCheckFailed;
}

int runFormat(const VerifyBijectionOptions& o, Run& run, std::ostream& out) {
  const auto f = vox::parseTexelFormat(o.format);
  if (!f) throw vox::Error(vox::ErrorKind::Usage, "--format " + o.format + ": expected rgba8, rgba16, rgba32ui, rgba16f or rgba32f");
  run.phase("measure");
  const uint64_t maxExact = vox::maxExactInteger(*f, run.threads());
  nlohmann::json j = {{"format", o.format}, {"max_exact_integer", maxExact}, {"first_inexact", maxExact + 1},
                      {"first_inexact_becomes", vox::roundTrip(*f, maxExact + 1)}};
  bool fits = true;
  std::string verdict;
  if (!o.dims.empty() || o.res) {
    vox::Dims d = {o.res, o.res, o.res};
    if (!o.dims.empty()) {
      const auto t = parseTriple(o.dims, "--dims");
      d = {t[0], t[1], t[2]};
    }
    const uint64_t maxCoord = uint64_t(d.maxAxis()) - 1;
    fits = maxCoord <= maxExact;
    j["dims"] = {d.x, d.y, d.z};
    j["max_coordinate"] = maxCoord;
    j["fits"] = fits;
    if (!fits) {
      const vox::TexelFormat ok = vox::narrowestExactFormat(maxCoord);
      j["would_work"] = vox::texelFormatName(ok);
      verdict = std::string(o.format) + " cannot hold coordinate " + std::to_string(maxExact + 1) + " of " +
                vox::toString(d) + " exactly (it becomes " + std::to_string(vox::roundTrip(*f, maxExact + 1)) +
                "); " + vox::texelFormatName(ok) + " would";
    } else {
      verdict = std::string(o.format) + " holds every coordinate of " + vox::toString(d) + " exactly";
    }
  }
  run.counts() = j;
  if (o.json) {
    out << j.dump(2) << "\n";
  } else {
    out << o.format << ": integers 0.." << maxExact << " round-trip exactly (measured); " << maxExact + 1
        << " becomes " << vox::roundTrip(*f, maxExact + 1) << "\n";
    if (!verdict.empty()) out << "  " << verdict << "\n" << (fits ? "OK" : "FAILED") << "\n";
  }
  return fits ? kExitOk : kExitCheckFailed;
}

}  // namespace

bool needsSceneModule(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    for (const char* opt : {"--atlas", "--scene", "--canonical"})
      if (a == opt || a.rfind(std::string(opt) + "=", 0) == 0) return true;
  }
  return false;
}

Command registerVerifyBijection(CLI::App& root) {
  auto o = std::make_shared<VerifyBijectionOptions>();
  CLI::App* cmd = root.add_subcommand("verify-bijection", "Prove the voxel<->texel mapping; check formats and built atlases");
  cmd->footer(
      "Modes:\n"
      "  --dims X,Y,Z | --res N     prove the mapping of that layout (exhaustive, or by parts when huge)\n"
      "  --format F [--dims ...]    measure which integers F holds exactly, and whether the dims fit\n"
      "  --atlas FILE --scene S     check a built atlas or bitmap against its scene\n"
      "  --canonical IMG --scene S  check a render-canonical image: every hit pixel decodes to an occupied\n"
      "                             voxel, and is the voxel a brute-force ray finds (camera: the image's own,\n"
      "                             or --camera/--eye...)\n"
      "Exit 0 when everything holds, 1 when a check fails (the first failure is printed).");
  cmd->add_option("--dims", o->dims, "Scene dims X,Y,Z");
  cmd->add_option("--res", o->res, "Cube dims N,N,N")->check(CLI::Range(1u, 1u << 30));
  cmd->add_option("--tiles-per-row", o->tilesPerRow, "Tiles per atlas row (default: smallest, squarest atlas)");
  cmd->add_option("--max-side", o->maxSide, "Largest texture side; more tile rows go to further layers")
      ->capture_default_str();
  cmd->add_option("--format", o->format, "rgba8 | rgba16 | rgba32ui | rgba16f | rgba32f");
  cmd->add_option("--atlas", o->atlas, "An atlas or bitmap image written by vox build-atlas");
  cmd->add_option("--scene", o->scene, "The scene the atlas was built from (or the render's scene / page file)");
  cmd->add_option("--canonical", o->canonical, "A canonical image written by vox render-canonical");
  addCameraOptions(*cmd, o->camera);
  const CLI::Option* budget =
      cmd->add_option("--check-budget", o->checkBudget,
                      "--canonical: ray-voxel tests the brute force may spend; past it, 1 pixel in K is checked (sampled 1 in K)")
          ->check(FinitePositive)
          ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the result as JSON on stdout");
  addCommonOptions(*cmd, o->common);
  return {cmd, [o, budget] {
            if (!o->canonical.empty()) {
              if (o->scene.empty()) throw vox::Error(vox::ErrorKind::Usage, "--canonical needs --scene (the scene or page file rendered)");
              if (!o->atlas.empty()) throw vox::Error(vox::ErrorKind::Usage, "give --atlas or --canonical, not both");
              o->camera.check();  // before the image and the scene are read
              // Without a camera on the command line the image's own is used whole.
              if (!o->camera.given() && (o->camera.fovGiven() || !o->camera.up.empty() || !o->camera.size.empty())) {
                const std::string option = o->camera.fovGiven() ? "--fov" : !o->camera.up.empty() ? "--up" : "--size";
                throw vox::Error(vox::ErrorKind::Usage,
                                 option + " shapes a camera given on the command line, and none is: the image's own "
                                          "camera is checked as it is; add --eye X,Y,Z --target X,Y,Z (or --camera "
                                          "FILE), or drop " + option);
              }
              if (o->camera.orbit > 1)
                throw vox::Error(vox::ErrorKind::Usage,
                                 "--orbit " + std::to_string(o->camera.orbit) + " makes " +
                                     std::to_string(o->camera.orbit) + " cameras, but " + o->canonical +
                                     " is one image; give the camera it was rendered from (--view NAME, --eye/--target, "
                                     "or --camera FILE --view INDEX), or none to check it with its own");
              return runCanonicalCheck(*o);
            }
            if (budget->count() > 0)
              throw vox::Error(vox::ErrorKind::Usage,
                               "--check-budget limits the brute force of --canonical, and --canonical is not given: add "
                               "--canonical IMG --scene S, or drop --check-budget");
            if (o->camera.given()) throw vox::Error(vox::ErrorKind::Usage, "camera options go with --canonical");
            if (!o->atlas.empty() || !o->scene.empty()) {
              if (o->atlas.empty() || o->scene.empty())
                throw vox::Error(vox::ErrorKind::Usage, "--atlas and --scene go together");
              return runAtlasCheck(*o);
            }
            Run run("verify-bijection", o->common);
            if (!o->format.empty()) {
              const int code = runFormat(*o, run, std::cout);
              return run.finish(code);
            }
            if (o->dims.empty() && o->res == 0)
              throw vox::Error(vox::ErrorKind::Usage, "give --dims X,Y,Z or --res N (or --format F, or --atlas with --scene)");
            if (!o->dims.empty() && o->res)
              throw vox::Error(vox::ErrorKind::Usage, "give --dims or --res, not both");
            const int code = runProof(*o, run, std::cout);
            return run.finish(code);
          }};
}

}  // namespace voxcli
