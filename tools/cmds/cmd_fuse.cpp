// vox fuse VIEWS.json [-i SCENE.vdb] -o SCENE.vdb: depth + label images voted
// into a scene, with free-space carving (docs/fuse.md). The rays and counts are
// libvox/render/fuse.h, the carve rule libvox/scene/fuse_scene.h, the views
// file formats/image/fuse_views.h, the `free` grid formats/vdb/fuse_vdb.h.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <map>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <iterator>
#include <optional>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/image/fuse_views.h"
#include "formats/vdb/fuse_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "libvox/core/memory_budget.h"
#include "libvox/core/parallel.h"
#include "libvox/render/fuse.h"
#include "libvox/render/fuse_memory.h"
#include "libvox/scene/fuse_scene.h"
#include "libvox/core/number_text.h"
#include "tools/cli/alloc_tuning.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/enum_option.h"

namespace voxcli {

namespace {

enum class CarveMode { On, Off, None };
enum class DepthKindOption { FromFile, Distance, Z };
enum class FreeOption { Voted, All };

struct FuseOptions {
  std::string views;
  std::string input;
  std::string output;
  DepthKindOption depthKind = DepthKindOption::FromFile;
  CarveMode carve = CarveMode::On;
  FreeOption free = FreeOption::Voted;
  uint32_t weight = 1;
  CommonOptions common;
  const CLI::App* app = nullptr;  // to tell an option given from its default
};

const EnumNames<CarveMode>& carveNames() {
  static const EnumNames<CarveMode> n{{"on", CarveMode::On}, {"off", CarveMode::Off}, {"none", CarveMode::None}};
  return n;
}
const EnumNames<FreeOption>& freeNames() {
  static const EnumNames<FreeOption> n{{"voted", FreeOption::Voted}, {"all", FreeOption::All}};
  return n;
}
const EnumNames<DepthKindOption>& depthKindNames() {
  static const EnumNames<DepthKindOption> n{
      {"file", DepthKindOption::FromFile}, {"distance", DepthKindOption::Distance}, {"z", DepthKindOption::Z}};
  return n;
}

std::string placementText(const vox::FuseGridSpec& g) {
  // 0.4 rather than 0.40000000000000002, yet two placements that differ never print alike.
  using vox::shortestText;
  return "dims " + vox::toString(g.dims) + ", voxel size " + shortestText(g.voxelSize) + ", origin (" +
         shortestText(g.origin[0]) + ", " + shortestText(g.origin[1]) + ", " + shortestText(g.origin[2]) + ")";
}

bool samePlacement(const vox::FuseGridSpec& a, const vox::FuseGridSpec& b) {
  return a.dims == b.dims && a.voxelSize == b.voxelSize && a.origin == b.origin;
}

/// What the second pass may keep of the views (their walked pixels,
/// vox::FuseWalks): a quarter of the run's memory limit, at most 2 GiB (above
/// that, reading the images again costs less than the memory).
uint64_t keptViewBudget(const vox::MemoryLimit& limit) {
  const uint64_t cap = uint64_t(2) << 30;
  return limit.unlimited() ? cap : std::min(cap, limit.bytes / 4);
}

/// Decodes views ahead, `batch` at a time in parallel (one image decode is
/// serial: PNG inflate, EXR zip), and hands them out in view order. A view
/// that fails to load throws when its turn comes, after the views before it:
/// the same error, at the same point, as loading one by one.
class ViewLoader {
 public:
  ViewLoader(const vox::FuseViewsFile& views, const vox::ClassTable& classes, std::optional<vox::DepthKind> kind,
             unsigned batch)
      : views_(views), classes_(classes), kind_(kind), batch_(std::max(1u, batch)), slots_(views.views.size()) {}
  /// View i (taken out: call once per i and pass); `ready` is a view already loaded.
  vox::LoadedFuseView take(size_t i) {
    if (!slots_[i].view && !slots_[i].error) {
      const size_t end = std::min(slots_.size(), i + batch_);
      vox::parallelForEach(end - i, batch_, 1, [&](size_t k) {
        Slot& s = slots_[i + k];
        if (s.view || s.error) return;
        try {
          s.view = vox::loadFuseView(views_.views[i + k], classes_, kind_);
        } catch (...) {
          s.error = std::current_exception();
        }
      });
    }
    Slot& s = slots_[i];
    if (s.error) std::rethrow_exception(s.error);
    vox::LoadedFuseView out = std::move(*s.view);
    s.view.reset();
    return out;
  }
  void put(size_t i, vox::LoadedFuseView&& v) { slots_[i].view = std::move(v); }
  /// Forget every view (before a second pass that loads them again).
  void reset() { slots_.assign(slots_.size(), Slot{}); }

 private:
  struct Slot {
    std::optional<vox::LoadedFuseView> view;
    std::exception_ptr error;
  };
  const vox::FuseViewsFile& views_;
  const vox::ClassTable& classes_;
  std::optional<vox::DepthKind> kind_;
  unsigned batch_;
  std::vector<Slot> slots_;
};

int runFuse(const FuseOptions& o) {
  if (!vox::hasExtension(o.output, ".vdb")) vox::throwUsage("-o " + o.output + ": the fused scene is written as OpenVDB; name it *.vdb");
  if (o.weight < 1 || o.weight > 65536) vox::throwUsage("--weight must be 1..65536 votes per pixel");
  Run run("fuse", o.common);
  if (!o.input.empty()) run.mayReplace(o.input);  // -i S -o S: votes added to S (docs/fuse.md)
  if (o.carve == CarveMode::None && o.app && o.app->get_option("--free")->count() > 0)
    vox::throwUsage("--free says where free space is counted, and --carve none counts none: drop --free, or "
                    "use --carve on or off");
  const std::string outTemp = run.output(o.output);

  run.phase("read");
  run.input(o.views);
  const vox::FuseViewsFile views = vox::readFuseViews(o.views);
  std::vector<std::string> warnings = views.warnings;
  // The same images twice vote twice: allowed (a view may be weighted so),
  // but said, as it is more often a copy-paste slip.
  {
    std::map<std::pair<std::string, std::string>, size_t> firstOf;
    for (size_t i = 0; i < views.views.size(); ++i) {
      const vox::FuseViewSpec& v = views.views[i];
      const auto key = std::make_pair(std::filesystem::path(v.depthPath).lexically_normal().string(),
                                      std::filesystem::path(v.labelPath).lexically_normal().string());
      const auto [it, added] = firstOf.emplace(key, i);
      if (!added)
        warnings.push_back(v.where + " has the depth and label images of views[" + std::to_string(it->second) +
                           "] (" + v.depthPath + ", " + v.labelPath + "): their pixels vote twice");
    }
  }
  for (const std::string& w : warnings) run.note("warning: " + w);
  std::optional<vox::DepthKind> kindOverride;
  if (o.depthKind == DepthKindOption::Distance) kindOverride = vox::DepthKind::Distance;
  if (o.depthKind == DepthKindOption::Z) kindOverride = vox::DepthKind::Z;

  // The grid and the classes: the input scene's, the views file's, or the first depth image's.
  std::optional<vox::Scene> base;
  vox::FuseCounts baseFree;  // the input's `free` grid
  vox::SceneHeader header;
  std::optional<vox::LoadedFuseView> first;
  if (!o.input.empty()) {
    run.input(o.input);
    vox::requireRegularFile(o.input);
    base = vox::readSceneVdb(o.input);
    vox::readFreeGrid(o.input, baseFree);
    header = base->header();
    if (header.mipLevel != 0) vox::throwBadInput(o.input + ": a mip level; fuse into a full-resolution scene");
    if (views.classes)
      vox::throwBadInput(views.path + ": \"classes\" is given, but -i " + o.input +
                         " has its own class table; remove \"classes\" (labels map to the scene's classes)");
    const vox::FuseGridSpec scene{header.dims, header.voxelSize, header.origin};
    if (views.grid && !samePlacement(*views.grid, scene))
      vox::throwBadInput(views.path + ": grid (" + placementText(*views.grid) + ") differs from -i " + o.input + " (" +
                         placementText(scene) + ")");
  } else {
    header.classes = views.classes ? *views.classes : vox::blockPalette();
    std::optional<vox::FuseGridSpec> grid = views.grid;
    if (!grid) {
      first = vox::loadFuseView(views.views[0], header.classes, kindOverride);
      grid = first->imageGrid;
      if (!grid)
        vox::throwBadInput(views.path + ": no grid: give \"grid\": {\"dims\", \"voxel_size\", \"origin\"}, -i SCENE.vdb, "
                           "or depth images from render-canonical (their vox:canonical entry has one)");
    }
    header.dims = grid->dims;
    header.voxelSize = grid->voxelSize;
    header.origin = grid->origin;
  }

  run.phase("fuse");
  vox::FuseSettings settings;
  const bool carve = o.carve == CarveMode::On;  // off: free counts are gathered, nothing removed
  settings.countFree = o.carve != CarveMode::None;  // none: votes only, no free-space walk
  // voted: free counts only where they can change a carve (voxels with votes,
  // now or in the input), in a second pass over the views that jumps empty bricks.
  settings.freeScope = o.free == FreeOption::Voted ? vox::FreeScope::Voted : vox::FreeScope::All;
  const bool secondPass = settings.countFree && settings.freeScope == vox::FreeScope::Voted;
  settings.weight = o.weight;
  settings.threads = run.threads();
  vox::GridFrame frame;
  frame.origin = header.origin;
  frame.voxelSize = header.voxelSize;
  vox::Fuser fuser(header.dims, frame, settings);
  // Voxels occupied in the input or voted by an earlier view: voxel keys,
  // sorted (each view's sorted keys are merged in: linear, no hashing).
  std::vector<uint64_t> seen, merged;
  if (base) base->forEachVoxel([&](const vox::VoxelView& v) { seen.push_back(vox::FuseCounts::voxelKey(v.at)); });
  std::sort(seen.begin(), seen.end());
  nlohmann::json perView = nlohmann::json::array();
  vox::FuseViewStats total;
  double fuseSeconds = 0;
  auto bar = run.progress("fuse");
  ViewLoader loader(views, header.classes, kindOverride, run.threads());
  if (!first) first = vox::loadFuseView(views.views[0], header.classes, kindOverride);
  // The second pass reads every view again unless the first pass's views,
  // as their walked pixels (vox::FuseWalks), fit the memory kept for them
  // (keptViewBudget): then it reuses those.
  const uint64_t keepBudget = secondPass ? keptViewBudget(run.memoryLimit()) : 0;
  // One arena and a heap in huge pages (tools/cli/alloc_tuning.h), before
  // the views are decoded ahead on the workers and once the first view is
  // read (its reading's freed buffers would otherwise stay resident in the
  // heap and count again in the estimate below): the decoded views, vote
  // tables and free counts arrived in 4 KB page faults, a fifth of a
  // fusion's CPU. growAdvisedHeap below covers the estimated peak.
  tuneAllocatorForShortRun();
  {
    // The memory guard, before the work: the first view's size stands for every view's.
    vox::FuseMemoryInputs mi;
    mi.dims = header.dims;
    mi.views = views.views.size();
    mi.pixelsPerView = uint64_t(first->view.camera.width) * first->view.camera.height;
    mi.threads = run.threads();
    mi.countFree = settings.countFree;
    mi.freeScope = settings.freeScope;
    mi.keptBudget = keepBudget;
    // The first view's walked pixels stand for every view's, as its size does.
    if (secondPass)
      mi.keptBytesPerView = vox::FuseWalks::bytesFor(fuser.walkedPixels(first->view), first->view.camera.width,
                                                     first->view.camera.height, !first->view.faceAxis.empty());
    auto estimateWith = [&](const vox::FuseMemoryInputs& in) {
      vox::MemoryEstimate e;
      e.add("resident after reading", vox::residentBytesNow());
      for (const vox::MemoryPart& p : vox::estimateFuseMemory(in).parts) e.parts.push_back(p);
      return e;
    };
    const vox::MemoryEstimate estimate = estimateWith(mi);
    std::string suggestion;
    const vox::MemoryLimit& limit = run.memoryLimit();
    if (!limit.unlimited() && estimate.bytes() > limit.bytes) {
      // The first setting that fits, from the least change: fewer threads,
      // free counts at voted voxels only, both; else fewer views per run.
      // With 1% (at least 1 MiB) to spare: the next run's resident memory differs a little.
      const double spare = std::max(double(1 << 20), 0.01 * double(limit.bytes));
      auto fits = [&](const vox::FuseMemoryInputs& in) { return double(estimateWith(in).bytes()) + spare <= double(limit.bytes); };
      std::vector<std::pair<std::string, vox::FuseMemoryInputs>> settingsToTry;
      vox::FuseMemoryInputs oneThread = mi, voted = mi;
      oneThread.threads = 1;
      voted.freeScope = vox::FreeScope::Voted;
      if (mi.threads > 1) settingsToTry.emplace_back("--threads 1", oneThread);
      if (mi.countFree && mi.freeScope == vox::FreeScope::All) {
        settingsToTry.emplace_back("--free voted", voted);
        voted.threads = 1;
        if (mi.threads > 1) settingsToTry.emplace_back("--free voted --threads 1", voted);
      }
      for (const auto& [text, in] : settingsToTry)
        if (suggestion.empty() && fits(in)) suggestion = text + " would need about " + vox::formatBytes(estimateWith(in).bytes());
      if (suggestion.empty()) {
        // The most views per run that fit (the estimate grows with the views).
        vox::FuseMemoryInputs fewer = settingsToTry.empty() ? mi : settingsToTry.back().second;
        uint64_t lo = 0, hi = mi.views;  // fewer.views = lo fits (or lo = 0), hi does not
        while (hi - lo > 1) {
          fewer.views = lo + (hi - lo) / 2;
          (fits(fewer) ? lo : hi) = fewer.views;
        }
        if (lo > 0) {
          fewer.views = lo;
          suggestion = "fuse at most " + counted(lo, "view", "views") + " per run" +
                       (settingsToTry.empty() ? "" : " with " + settingsToTry.back().first) +
                       " (about " + vox::formatBytes(estimateWith(fewer).bytes()) + "; votes add up across runs with -i)";
        }
      }
    }
    run.checkMemory(estimate,
                    "fusing " + counted(mi.views, "view", "views") + " of " + std::to_string(first->view.camera.width) + "x" +
                        std::to_string(first->view.camera.height) + " into a " + vox::toString(header.dims) + " grid",
                    suggestion);
    growAdvisedHeap(estimate.bytes());
  }
  loader.put(0, std::move(*first));
  first.reset();
  uint64_t keptBytes = 0;
  bool keepViews = secondPass;
  std::vector<vox::FuseWalks> kept;
  for (size_t i = 0; i < views.views.size(); ++i) {
    const vox::FuseViewSpec& spec = views.views[i];
    vox::LoadedFuseView loaded = loader.take(i);
    for (const std::string& f : loaded.files) run.input(f);
    if (loaded.imageGrid && !views.grid && !samePlacement(*loaded.imageGrid, {header.dims, header.voxelSize, header.origin}))
      run.note("warning: " + spec.where + ": " + spec.depthPath + " was rendered from a grid of " +
               placementText(*loaded.imageGrid) + "; fusing into " +
               placementText({header.dims, header.voxelSize, header.origin}));
    const auto t0 = std::chrono::steady_clock::now();
    const vox::FuseViewStats s = fuser.add(loaded.view);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fuseSeconds += secs;
    merged.clear();
    std::set_union(seen.begin(), seen.end(), s.votedKeys.begin(), s.votedKeys.end(), std::back_inserter(merged));
    const uint64_t newVoxels = merged.size() - seen.size();
    seen.swap(merged);
    perView.push_back({{"view", i},
                       {"depth", spec.depthPath},
                       {"label", spec.labelPath},
                       {"size", {loaded.view.camera.width, loaded.view.camera.height}},
                       {"pixels", s.pixels},
                       {"used", s.used},
                       {"ambiguous", s.ambiguous},
                       {"skipped", {{"no_depth", s.noDepth}, {"no_class", s.unlabelled}, {"zero_confidence", s.zeroWeight}, {"outside_grid", s.outside}}},
                       {"voxels_voted", s.voxelsVoted},
                       {"voxels_new", newVoxels},
                       {"free_counts", s.freeCounts},
                       {"steps", s.steps},
                       {"seconds", secs}});
    total.pixels += s.pixels;
    total.used += s.used;
    total.ambiguous += s.ambiguous;
    total.noDepth += s.noDepth;
    total.unlabelled += s.unlabelled;
    total.zeroWeight += s.zeroWeight;
    total.outside += s.outside;
    total.steps += s.steps;
    total.freeCounts += s.freeCounts;
    if (keepViews) {
      // The pixels the second pass walks, kept instead of the decoded view,
      // whose memory the next view's decoding then reuses.
      const auto k0 = std::chrono::steady_clock::now();
      vox::FuseWalks walks = fuser.walksOf(loaded.view);
      const double keepSecs = std::chrono::duration<double>(std::chrono::steady_clock::now() - k0).count();
      fuseSeconds += keepSecs;
      perView.back()["seconds"] = perView.back()["seconds"].get<double>() + keepSecs;
      keptBytes += walks.bytes();
      keepViews = keptBytes <= keepBudget;
      if (keepViews) kept.push_back(std::move(walks));
      else kept = {};
    }
    if (bar) bar->update(double(i + 1) / double(views.views.size()) * (secondPass ? 0.5 : 1.0));
  }
  if (secondPass) {
    // Second pass: free counts at the voxels with votes, the input's occupied
    // voxels and its `free` entries (docs/fuse.md, "Free space").
    std::vector<vox::Coord3> extra;
    if (base) base->forEachVoxel([&](const vox::VoxelView& v) { extra.push_back(v.at); });
    for (const auto& [c, n] : baseFree.freeVoxels()) extra.push_back(c);
    fuser.track(extra);
    extra = {};
    loader.reset();
    for (size_t i = 0; i < views.views.size(); ++i) {
      std::optional<vox::FuseView> view;
      if (!keepViews) view = std::move(loader.take(i).view);
      const auto t0 = std::chrono::steady_clock::now();
      const vox::FuseViewStats s = keepViews ? fuser.addFree(kept[i]) : fuser.addFree(*view);
      if (keepViews) kept[i] = {};
      view.reset();
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      fuseSeconds += secs;
      nlohmann::json& v = perView[i];
      v["free_counts"] = v["free_counts"].get<uint64_t>() + s.freeCounts;
      v["steps"] = v["steps"].get<uint64_t>() + s.steps;
      v["seconds"] = v["seconds"].get<double>() + secs;
      total.steps += s.steps;
      total.freeCounts += s.freeCounts;
      if (bar) bar->update(0.5 + double(i + 1) / double(views.views.size()) * 0.5);
    }
  }
  if (bar) bar->done();

  run.phase("carve");
  vox::FuseCounts counts = std::move(fuser).finish();
  counts.merge(std::move(baseFree));
  vox::FusedScene fused = vox::applyFusion(header, base ? &*base : nullptr, std::move(counts), carve);
  base.reset();

  run.phase("write");
  vox::writeFusedSceneVdb(fused.scene, std::move(fused.free), outTemp);

  const vox::FuseTotals& t = fused.totals;
  const uint64_t rays = total.used + total.outside;
  run.counts()["views"] = perView;
  if (total.ambiguous > 0) {
    const std::string w = counted(total.ambiguous, "pixel's ray runs", "pixels' rays run") +
                          " along a grid plane or through a voxel edge (ambiguous): a depth cannot tell which of the "
                          "voxels touched there was seen, so such a vote may land beside it (a named view at an odd "
                          "image size has a row and a column of such rays: its eye is on grid planes)";
    run.note("warning: " + w);
    warnings.push_back(w);
  }
  if (total.used == 0) {
    const std::string w = "no pixel of " + counted(views.views.size(), "view", "views") +
                          " reached a voxel of the grid (" + placementText({header.dims, header.voxelSize, header.origin}) +
                          "): nothing was voted; check the cameras and depths against the grid";
    run.note("warning: " + w);
    warnings.push_back(w);
  }
  run.counts()["warnings"] = warnings;
  run.counts()["totals"] = {{"views", views.views.size()},
                            {"pixels", total.pixels},
                            {"used", total.used},
                            {"ambiguous", total.ambiguous},
                            {"skipped", {{"no_depth", total.noDepth}, {"no_class", total.unlabelled}, {"zero_confidence", total.zeroWeight}, {"outside_grid", total.outside}}},
                            {"rays", rays},
                            {"steps", total.steps},
                            {"steps_per_ray", rays ? double(total.steps) / double(rays) : 0.0},
                            {"free_counts", total.freeCounts},
                            {"rays_per_second", fuseSeconds > 0 ? double(rays) / fuseSeconds : 0.0},
                            {"fuse_seconds", fuseSeconds},
                            {"occupied_before", t.occupiedBefore},
                            {"occupied_after", t.occupiedAfter},
                            {"voxels_voted", t.voxelsVoted},
                            {"created", t.created},
                            {"removed", t.removed},
                            {"rejected", t.rejected},
                            {"free_voxels", t.freeVoxels},
                            {"colored", t.colored},
                            {"pixels_per_second", fuseSeconds > 0 ? double(total.pixels) / fuseSeconds : 0.0},
                            {"carve", nameOf(carveNames(), o.carve)},
                            {"free", nameOf(freeNames(), o.free)},
                            {"weight", settings.weight}};
  if (secondPass) run.counts()["totals"]["second_pass_views"] = keepViews ? "kept" : "read again";
  char line[400];
  std::snprintf(line, sizeof line,
                "%s, %llu pixels: %llu voted, %llu skipped (no depth %llu, no class %llu, zero confidence %llu, outside "
                "the grid %llu); "
                "%llu voxels occupied (%llu before, %llu created, %llu removed by carving), %llu with free counts",
                counted(views.views.size(), "view", "views").c_str(), (unsigned long long)total.pixels, (unsigned long long)total.used,
                (unsigned long long)(total.noDepth + total.unlabelled + total.zeroWeight + total.outside), (unsigned long long)total.noDepth,
                (unsigned long long)total.unlabelled, (unsigned long long)total.zeroWeight, (unsigned long long)total.outside,
                (unsigned long long)t.occupiedAfter, (unsigned long long)t.occupiedBefore, (unsigned long long)t.created,
                (unsigned long long)t.removed, (unsigned long long)t.freeVoxels);
  run.note(line);
  run.noteWhenDone("wrote " + o.output);
  return run.finish();
}

}  // namespace

Command registerFuse(CLI::App& root) {
  auto opts = std::make_shared<FuseOptions>();
  CLI::App* cmd = root.add_subcommand("fuse", "Vote depth + label images into a scene, carving free space");
  opts->app = cmd;
  cmd->footer(
      "Each pixel with a depth and a class votes for the voxel its ray (render-canonical's ray\n"
      "through the pixel centre) reaches at that depth; the voxels the ray crossed before it get a\n"
      "free count (grid 'free'); a voxel whose free count exceeds its votes is removed (--carve off\n"
      "keeps everything, --carve none counts no free space). -i adds to an existing scene (votes and\n"
      "free counts add up). Optional per view: normal (ties), color and confidence images.\n"
      "VIEWS.json: {\"views\": [{\"depth\": \"v.depth.exr\", \"label\": \"v.class.png\", \"camera\": ...}], ...};\n"
      "docs/fuse.md has the file, the tie rules and the report.\n"
      "Example: vox render-canonical s.vdb -o v.png --orbit 6 --mode depth,class && vox fuse views.json -o fused.vdb");
  cmd->add_option("views", opts->views, "Views file (.json)")->required();
  cmd->add_option("-i,--input", opts->input, "Scene to add to (.vdb); default: a fresh grid");
  cmd->add_option("-o,--output", opts->output, "Fused scene (*.vdb)")->required();
  addEnumOption(*cmd, "--depth-kind", opts->depthKind, depthKindNames(),
                "distance (from the eye along the ray, render-canonical's) or z (camera-space depth); "
                "default: the views file's, else distance");
  addEnumOption(*cmd, "--carve", opts->carve, carveNames(),
                "on: count free space and remove voxels whose free count exceeds their votes; off: count, remove "
                "nothing; none: votes only (no free-space walk, fastest)");
  addEnumOption(*cmd, "--free", opts->free, freeNames(),
                "where free counts are kept: voted (default: voxels with votes, now or in -i's scene or free grid; "
                "fast) or all (every voxel a ray crosses: runs with -i add up exactly like one run; slow)");
  cmd->add_option("--weight", opts->weight, "Votes per pixel (1..65536), times the view's confidence image if any")->default_val(1);
  addCommonOptions(*cmd, opts->common);
  return {cmd, [opts] { return runFuse(*opts); }};
}

}  // namespace voxcli
