#include "libvox/scene/mip.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "libvox/core/counted.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {

using BoolLeaf = openvdb::BoolTree::LeafNodeType;
using IntLeaf = openvdb::Int32Tree::LeafNodeType;
using ColorLeaf = openvdb::Vec3STree::LeafNodeType;

bool coordLess(const openvdb::Coord& a, const openvdb::Coord& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

// The output of one coarse 8^3 leaf (null members: nothing there).
struct CoarseLeaf {
  std::unique_ptr<BoolLeaf> occupancy;
  std::vector<std::unique_ptr<IntLeaf>> votes;  // per class index of the fine scene
  std::unique_ptr<ColorLeaf> color;
};

// Scratch space of one worker, reused across coarse leaves.
struct Scratch {
  std::array<uint8_t, 512> count{};      // occupied children
  std::array<uint8_t, 512> surface{};    // OR of children's flags
  std::vector<std::array<int64_t, 512>> votes;  // per class index
  std::vector<uint8_t> classTouched;
  std::array<std::array<double, 3>, 512> colorSum{};
  std::array<uint8_t, 512> colorCount{};
};

}  // namespace

uint64_t surfaceCount(const Scene& scene) {
  uint64_t n = 0;
  for (auto it = scene.grids().occupancy->cbeginValueOn(); it; ++it) n += *it ? 1 : 0;
  return n;
}

Scene reduceScene(const Scene& fine, MipOccupancy mode, unsigned threads) {
  const SceneHeader& fh = fine.header();
  const SceneGrids& fg = fine.grids();
  const size_t nClasses = fg.votes.size();
  const bool hasColor = fg.color != nullptr;
  const Dims fd = fh.dims;

  // Coarse leaves: each fine leaf at origin o feeds the coarse leaf holding o/2.
  std::vector<openvdb::Coord> origins;
  for (auto leaf = fg.occupancy->tree().cbeginLeaf(); leaf; ++leaf) {
    const openvdb::Coord o = leaf->origin();
    origins.emplace_back((o.x() >> 1) & ~7, (o.y() >> 1) & ~7, (o.z() >> 1) & ~7);
  }
  std::sort(origins.begin(), origins.end(), coordLess);
  origins.erase(std::unique(origins.begin(), origins.end()), origins.end());

  // One range of coarse leaves per thread, each with its own scratch space;
  // every leaf is written to its own slot, so the split does not matter.
  std::vector<CoarseLeaf> out(origins.size());
  const unsigned pieces = std::max(1u, std::min<unsigned>(threads, unsigned(std::max<size_t>(1, origins.size()))));
  parallelPieces(origins.size(), pieces, pieces, [&](size_t begin, size_t end, size_t) {
    auto s = std::make_unique<Scratch>();
    s->votes.resize(nClasses);
    s->classTouched.resize(nClasses);
    std::vector<const IntLeaf*> voteLeaves(nClasses);
    for (size_t li = begin; li < end; ++li) {
      const openvdb::Coord co = origins[li];
      s->count.fill(0);
      s->surface.fill(0);
      s->colorCount.fill(0);
      std::fill(s->classTouched.begin(), s->classTouched.end(), 0);
      bool anyColor = false;
      // The 8 fine leaves of this coarse leaf, in a fixed order.
      for (int d = 0; d < 8; ++d) {
        const int dx = (d >> 2) & 1, dy = (d >> 1) & 1, dz = d & 1;
        const openvdb::Coord fo(2 * co.x() + 8 * dx, 2 * co.y() + 8 * dy, 2 * co.z() + 8 * dz);
        const BoolLeaf* occ = fg.occupancy->tree().probeConstLeaf(fo);
        if (!occ) continue;
        for (size_t c = 0; c < nClasses; ++c) {
          voteLeaves[c] = fg.votes[c].grid->tree().probeConstLeaf(fo);
          if (voteLeaves[c] && !s->classTouched[c]) {
            s->classTouched[c] = 1;
            s->votes[c].fill(0);
          }
        }
        const ColorLeaf* col = hasColor ? fg.color->tree().probeConstLeaf(fo) : nullptr;
        for (auto it = occ->cbeginValueOn(); it; ++it) {
          const openvdb::Index off = it.pos();
          const int fx = int(off >> 6), fy = int((off >> 3) & 7), fz = int(off & 7);
          const int cx = (8 * dx + fx) >> 1, cy = (8 * dy + fy) >> 1, cz = (8 * dz + fz) >> 1;
          const size_t co_ = size_t((cx << 6) | (cy << 3) | cz);
          ++s->count[co_];
          if (*it) s->surface[co_] = 1;
          for (size_t c = 0; c < nClasses; ++c)
            if (voteLeaves[c] && voteLeaves[c]->isValueOn(off)) s->votes[c][co_] += voteLeaves[c]->getValue(off);
          if (col && col->isValueOn(off)) {
            if (s->colorCount[co_] == 0) s->colorSum[co_] = {0, 0, 0};
            const openvdb::Vec3s& v = col->getValue(off);
            for (int k = 0; k < 3; ++k) s->colorSum[co_][k] += double(v[k]);
            ++s->colorCount[co_];
            anyColor = true;
          }
        }
      }
      CoarseLeaf& L = out[li];
      L.votes.resize(nClasses);
      for (openvdb::Index off = 0; off < 512; ++off) {
        const uint32_t n = s->count[off];
        if (n == 0) continue;
        if (mode == MipOccupancy::Majority) {
          // Children of coarse voxel X on an axis: 2X and 2X+1, the latter only inside the fine dims.
          const int64_t X = co.x() + int64_t(off >> 6), Y = co.y() + int64_t((off >> 3) & 7), Z = co.z() + int64_t(off & 7);
          auto inside = [](int64_t c, uint32_t dim) { return 2 * c + 1 < int64_t(dim) ? 2u : 1u; };
          const uint32_t children = inside(X, fd.x) * inside(Y, fd.y) * inside(Z, fd.z);
          if (2 * n < children) continue;
        }
        if (!L.occupancy) L.occupancy = std::make_unique<BoolLeaf>(co, false);
        L.occupancy->setValueOn(off, s->surface[off] != 0);
        for (size_t c = 0; c < nClasses; ++c) {
          if (!s->classTouched[c] || s->votes[c][off] == 0) continue;
          if (!L.votes[c]) L.votes[c] = std::make_unique<IntLeaf>(co, 0);
          L.votes[c]->setValueOn(off, int32_t(std::min<int64_t>(s->votes[c][off], kMaxVotesPerClass)));
        }
        if (anyColor && s->colorCount[off]) {
          if (!L.color) L.color = std::make_unique<ColorLeaf>(co, openvdb::Vec3s(0.f));
          const double k = 1.0 / s->colorCount[off];
          L.color->setValueOn(off, openvdb::Vec3s(float(s->colorSum[off][0] * k), float(s->colorSum[off][1] * k),
                                                  float(s->colorSum[off][2] * k)));
        }
      }
    }
  });

  Scene coarse;
  coarse.header() = coarserMipHeader(fh);
  SceneGrids& g = coarse.grids();
  std::vector<openvdb::Int32Grid::Ptr> voteGrids(nClasses);
  for (size_t c = 0; c < nClasses; ++c) voteGrids[c] = openvdb::Int32Grid::create(0);
  if (hasColor) g.color = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.f));
  for (CoarseLeaf& L : out) {
    if (!L.occupancy) continue;
    g.occupancy->tree().addLeaf(L.occupancy.release());
    for (size_t c = 0; c < nClasses; ++c)
      if (L.votes[c]) voteGrids[c]->tree().addLeaf(L.votes[c].release());
    if (L.color) g.color->tree().addLeaf(L.color.release());
  }
  for (size_t c = 0; c < nClasses; ++c)
    if (!voteGrids[c]->tree().empty()) {
      voteGrids[c]->setName("votes." + std::to_string(fg.votes[c].classId));
      g.votes.push_back({fg.votes[c].classId, voteGrids[c]});
    }
  if (g.color) g.color->setName("color");
  return coarse;
}

std::vector<Scene> buildMipPyramid(const Scene& base, const MipSettings& settings) {
  const int reachable = maxMipLevels(base.header().dims);
  if (settings.levels < 0 || settings.levels > reachable)
    throwUsage(std::to_string(settings.levels) + (settings.levels == 1 ? " pyramid level" : " pyramid levels") +
                   " asked for: a " +
                   toString(base.header().dims) + " grid has " +
                   (reachable == 0 ? std::string("no coarser level (it is one voxel)")
                                   : "at most " + counted(uint64_t(reachable), "coarser level", "coarser levels") +
                                         " (one voxel at level " + std::to_string(reachable) + ")"),
               Setting::MipLevels);
  std::vector<Scene> levels;
  if (settings.levels == 0 && base.occupiedCount() <= 1) return levels;  // nothing new to say
  const int want = settings.levels ? settings.levels : reachable;
  for (int n = 1; n <= want; ++n) {
    const auto t0 = std::chrono::steady_clock::now();
    const Scene& fine = levels.empty() ? base : levels.back();
    levels.push_back(reduceScene(fine, settings.occupancy, settings.threads));
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (settings.onLevel) settings.onLevel(n, levels.back(), secs);
    if (settings.levels == 0 && levels.back().occupiedCount() <= 1) break;
  }
  return levels;
}

std::string placementMismatch(const SceneHeader& a, const SceneHeader& b) {
  if (!(a.dims == b.dims)) return "dims " + toString(a.dims) + " vs " + toString(b.dims);
  const double tol = 1e-9 * std::max(a.voxelSize, b.voxelSize);
  if (std::abs(a.voxelSize - b.voxelSize) > tol)
    return "voxel size " + std::to_string(a.voxelSize) + " vs " + std::to_string(b.voxelSize);
  for (int k = 0; k < 3; ++k)
    if (std::abs(a.origin[k] - b.origin[k]) > 1e-6 * std::max(a.voxelSize, b.voxelSize))
      return "origin differs on axis " + std::to_string(k);
  return {};
}

namespace {
uint8_t winner(std::span<const ClassVotes> votes) {
  uint8_t best = 0;
  uint32_t top = 0;
  for (const ClassVotes& c : votes)
    if (c.votes > top) top = c.votes, best = c.classId;  // sorted by id: ties keep the lowest
  return best;
}
}  // namespace

MipComparison compareWithReference(const Scene& mip, const Scene& reference) {
  MipComparison r;
  r.mipVoxels = mip.occupiedCount();
  r.referenceVoxels = reference.occupiedCount();
  const ClassTable& ta = mip.header().classes;
  const ClassTable& tb = reference.header().classes;
  std::vector<ClassVotes> storage;
  mip.forEachVoxel([&](const VoxelView& v) {
    const auto ref = reference.voxel(v.at, storage);
    if (!ref) {
      ++r.onlyMip;
      return;
    }
    ++r.both;
    const ClassInfo* ca = ta.find(winner(v.votes));
    const ClassInfo* cb = tb.find(winner(ref->votes));
    if (!ca || !cb || ca->name != cb->name) ++r.classDisagree;
  });
  r.onlyReference = r.referenceVoxels - r.both;
  const uint64_t uni = r.both + r.onlyMip + r.onlyReference;
  r.iou = uni ? double(r.both) / double(uni) : 1.0;
  r.classDisagreement = r.both ? double(r.classDisagree) / double(r.both) : 0.0;
  return r;
}

}  // namespace vox
