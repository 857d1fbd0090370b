#include "libvox/scene/fuse_scene.h"

#include <algorithm>
#include <optional>
#include <unordered_map>

namespace vox {

namespace {

struct Existing {
  Coord3 at;
  bool surface = false;
  std::optional<RgbLinear> color;
  std::vector<ClassVotes> votes;
  uint64_t total = 0;
};

}  // namespace

FusedScene applyFusion(const SceneHeader& header, const Scene* base, FuseCounts&& counts, bool carve) {
  FusedScene out;
  // Input voxels, by key.
  std::vector<Existing> existing;
  std::unordered_map<uint64_t, size_t> indexOf;
  if (base) {
    base->forEachVoxel([&](const VoxelView& v) {
      Existing e;
      e.at = v.at;
      e.surface = v.surface;
      e.color = v.color;
      e.votes.assign(v.votes.begin(), v.votes.end());
      e.total = v.totalVotes();
      indexOf.emplace(FuseCounts::voxelKey(v.at), existing.size());
      existing.push_back(std::move(e));
    });
  }
  out.totals.occupiedBefore = existing.size();

  // Free counts (the input's and the new ones) stay in the counts' bricks,
  // which become the output's.
  // New votes grouped by voxel (sorted by voxel key, then class).
  const std::vector<FuseCounts::Vote> votes = counts.votes();
  const auto& colors = counts.colorSums();
  FuseCounts& freeOf = counts;

  SceneBuilder builder(header);
  auto clampVotes = [](uint64_t n) { return uint32_t(std::min<uint64_t>(n, kMaxVotesPerClass)); };
  std::vector<bool> existingDone(existing.size(), false);
  for (size_t i = 0; i < votes.size();) {
    size_t j = i;
    uint64_t newTotal = 0;
    const uint64_t key = FuseCounts::voxelKey(votes[i].at);
    while (j < votes.size() && FuseCounts::voxelKey(votes[j].at) == key) newTotal += votes[j++].votes;
    ++out.totals.voxelsVoted;
    const auto ex = indexOf.find(key);
    const Existing* e = ex == indexOf.end() ? nullptr : &existing[ex->second];
    if (e) existingDone[ex->second] = true;
    const uint64_t V = newTotal + (e ? e->total : 0);
    const uint64_t F = freeOf.freeAt(votes[i].at);
    if (carve && F > V) {
      freeOf.setFree(votes[i].at, uint32_t(F - V));
      if (e) ++out.totals.removed;
      else ++out.totals.rejected;
    } else {
      if (e) {
        for (const ClassVotes& cv : e->votes) builder.addVotes(e->at, cv.classId, cv.votes, e->surface);
        if (e->color) builder.setColor(e->at, *e->color);
      } else {
        ++out.totals.created;
      }
      for (size_t k = i; k < j; ++k)
        builder.addVotes(votes[k].at, votes[k].classId, clampVotes(votes[k].votes), e ? e->surface : true);
      // The new colour samples' average replaces an input colour.
      const auto col = colors.find(key);
      if (col != colors.end() && col->second.n) {
        const double scale = 1.0 / (16777216.0 * double(col->second.n));
        builder.setColor(votes[i].at, RgbLinear{float(double(col->second.r) * scale), float(double(col->second.g) * scale),
                                                float(double(col->second.b) * scale)});
        ++out.totals.colored;
      }
      ++out.totals.occupiedAfter;
    }
    i = j;
  }
  // Input voxels without new votes.
  for (size_t i = 0; i < existing.size(); ++i) {
    if (existingDone[i]) continue;
    const Existing& e = existing[i];
    const uint64_t F = freeOf.freeAt(e.at);
    if (carve && F > e.total) {
      freeOf.setFree(e.at, uint32_t(F - e.total));
      ++out.totals.removed;
      continue;
    }
    for (const ClassVotes& cv : e.votes) builder.addVotes(e.at, cv.classId, cv.votes, e.surface);
    if (e.color) builder.setColor(e.at, *e.color);
    ++out.totals.occupiedAfter;
  }
  out.scene = std::move(builder).build();
  // The free grid: net counts where the rule emptied a voxel, the total elsewhere.
  counts.dropVotes();
  out.free = std::move(counts);
  out.free.forEachFreeBrick([&](Coord3, const uint32_t* n) {
    for (int i = 0; i < 512; ++i) out.totals.freeVoxels += n[i] ? 1 : 0;
  });
  return out;
}

}  // namespace vox
