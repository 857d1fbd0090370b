#include "libvox/scene/scene_diff.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <tuple>

#include "libvox/core/number_text.h"
#include "libvox/core/parallel.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

const char* voxelDiffKindName(VoxelDiffKind kind) {
  switch (kind) {
    case VoxelDiffKind::Occupancy: return "occupancy";
    case VoxelDiffKind::Votes: return "votes";
    case VoxelDiffKind::Color: return "color";
    case VoxelDiffKind::Surface: return "surface";
  }
  return "?";
}

std::array<double, 3> voxelCentreWorld(const SceneHeader& h, Coord3 c) {
  return {h.origin[0] + (c.u + 0.5) * h.voxelSize, h.origin[1] + (c.v + 0.5) * h.voxelSize,
          h.origin[2] + (c.w + 0.5) * h.voxelSize};
}

namespace {

// Exact but short: "0.8", not "0.80000000000000004".
std::string num(double x) { return shortestText(x); }

std::string triple(const std::array<double, 3>& v) { return num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]); }

std::string classText(const ClassInfo* c) {
  if (!c) return "absent";
  char hex[8];
  std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c->color.r, c->color.g, c->color.b);
  std::string s = c->name + " " + hex;
  if (c->faces) s += " (faces)";
  return s;
}

std::string sourceText(const SceneSource& s) {
  return s.kind + " " + s.path + (s.sha256.empty() ? "" : " sha256 " + s.sha256.substr(0, 16)) + " " +
         std::to_string(s.bytes) + " bytes";
}

bool sameSourceContent(const SceneSource& a, const SceneSource& b) {
  // A different path to the same bytes is the same source; built-in inputs
  // (no digest) are known by their name.
  if (a.sha256.empty() || b.sha256.empty()) return a == b;
  return a.kind == b.kind && a.sha256 == b.sha256 && a.bytes == b.bytes;
}

void compareHeaders(const SceneHeader& a, const SceneHeader& b, const SceneDiffOptions& o, SceneDiff& d) {
  if (!(a.dims == b.dims)) d.header.push_back({"dims", toString(a.dims), toString(b.dims)});
  if (a.voxelSize != b.voxelSize) d.header.push_back({"voxel_size", num(a.voxelSize), num(b.voxelSize)});
  if (a.origin != b.origin) d.header.push_back({"origin", triple(a.origin), triple(b.origin)});
  if (a.mipLevel != b.mipLevel)
    d.header.push_back({"mip_level", std::to_string(a.mipLevel), std::to_string(b.mipLevel)});
  if (a.blockWorld != b.blockWorld) {
    auto text = [](const std::optional<BlockWorldPlacement>& p) {
      if (!p) return std::string("none");
      return "world scale " + num(p->worldScale) + ", grid " + std::to_string(p->gridSize[0]) + " x " +
             std::to_string(p->gridSize[1]) + " x " + std::to_string(p->gridSize[2]);
    };
    d.header.push_back({"block_world", text(a.blockWorld), text(b.blockWorld)});
  }
  if (a.region != b.region) {
    auto text = [](const std::optional<SceneRegion>& r) {
      if (!r) return std::string("whole scene");
      std::string s = "part " + std::to_string(r->index) + "/" + std::to_string(r->count) + ", box ";
      s += r->box.empty() ? std::string("empty") : toString(r->box.min) + " .. " + toString(r->box.max);
      return s + ", world " + r->worldKey.substr(0, 12);
    };
    d.header.push_back({"region", text(a.region), text(b.region)});
  }
  if (!o.ignoreSources) {
    bool same = a.sources.size() == b.sources.size();
    for (size_t i = 0; same && i < a.sources.size(); ++i) same = sameSourceContent(a.sources[i], b.sources[i]);
    if (!same) {
      auto text = [](const std::vector<SceneSource>& v) {
        std::string s;
        for (const SceneSource& x : v) s += (s.empty() ? "" : "; ") + sourceText(x);
        return s.empty() ? std::string("none") : s;
      };
      d.header.push_back({"sources", text(a.sources), text(b.sources)});
    }
  }
  // Class tables: by id, so a renamed or recoloured class is named.
  std::vector<uint8_t> ids;
  for (const ClassInfo& c : a.classes.classes()) ids.push_back(c.id);
  for (const ClassInfo& c : b.classes.classes()) ids.push_back(c.id);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  for (uint8_t id : ids) {
    const ClassInfo* ca = a.classes.find(id);
    const ClassInfo* cb = b.classes.find(id);
    if (ca && cb && *ca == *cb) continue;
    d.classes.push_back({id, classText(ca), classText(cb)});
  }
}

auto orderKey(Coord3 c) { return std::tuple(c.w, c.v, c.u); }

using BoolLeaf = openvdb::BoolTree::LeafNodeType;
using IntLeaf = openvdb::Int32Tree::LeafNodeType;
using ColorLeaf = openvdb::Vec3STree::LeafNodeType;

// The leaves of one scene at one leaf origin, with the vote leaves in the
// order of the union of both scenes' class ids (nullptr where absent).
struct SideLeaves {
  const BoolLeaf* occ = nullptr;
  std::vector<const IntLeaf*> votes;
  const ColorLeaf* color = nullptr;
};

// The vote grid of each class of `ids` in `s` (nullptr when absent).
std::vector<const openvdb::Int32Grid*> voteGridsFor(const Scene& s, const std::vector<uint8_t>& ids) {
  std::vector<const openvdb::Int32Grid*> out(ids.size(), nullptr);
  for (const ClassGrid& g : s.grids().votes) {
    const auto at = std::lower_bound(ids.begin(), ids.end(), g.classId);
    out[size_t(at - ids.begin())] = g.grid.get();
  }
  return out;
}

SideLeaves probe(const Scene& s, const std::vector<const openvdb::Int32Grid*>& voteGrids, const openvdb::Coord& o) {
  SideLeaves l;
  l.occ = s.grids().occupancy->tree().probeConstLeaf(o);
  l.votes.resize(voteGrids.size(), nullptr);
  for (size_t k = 0; k < voteGrids.size(); ++k)
    if (voteGrids[k]) l.votes[k] = voteGrids[k]->tree().probeConstLeaf(o);
  if (s.grids().color) l.color = s.grids().color->tree().probeConstLeaf(o);
  return l;
}

// Active values and masks equal (inactive values are ignored).
template <typename Leaf>
bool sameLeaf(const Leaf* a, const Leaf* b) {
  if (!a || !b) return a == b;
  if (a->getValueMask() != b->getValueMask()) return false;
  if constexpr (std::is_same_v<Leaf, BoolLeaf>) {
    // Bool leaves store values as a bit mask: compare the active bits only.
    const openvdb::Index64* va = a->buffer().data();
    const openvdb::Index64* vb = b->buffer().data();
    const auto& mask = a->getValueMask();
    for (openvdb::Index k = 0; k < BoolLeaf::NodeMaskType::WORD_COUNT; ++k)
      if ((va[k] ^ vb[k]) & mask.template getWord<openvdb::Index64>(k)) return false;
    return true;
  } else {
    for (auto it = a->getValueMask().beginOn(); it; ++it)
      if (a->getValue(it.pos()) != b->getValue(it.pos())) return false;
    return true;
  }
}

VoxelValues valuesAt(const SideLeaves& l, const std::vector<uint8_t>& ids, openvdb::Index n) {
  VoxelValues v;
  if (!l.occ || !l.occ->isValueOn(n)) return v;
  v.occupied = true;
  v.surface = l.occ->getValue(n);
  for (size_t k = 0; k < ids.size(); ++k)
    if (l.votes[k] && l.votes[k]->isValueOn(n)) v.votes.push_back({ids[k], uint32_t(l.votes[k]->getValue(n))});
  if (l.color && l.color->isValueOn(n)) {
    const openvdb::Vec3s& c = l.color->getValue(n);
    v.color = RgbLinear{c[0], c[1], c[2]};
  }
  return v;
}

void mergeKind(VoxelKindDiff& into, const VoxelKindDiff& from) {
  into.count += from.count;
  if (from.first && (!into.first || orderKey(from.first->at) < orderKey(into.first->at))) into.first = from.first;
  if (from.worst && (!into.worst || from.worst->magnitude > into.worst->magnitude ||
                     (from.worst->magnitude == into.worst->magnitude &&
                      orderKey(from.worst->at) < orderKey(into.worst->at))))
    into.worst = from.worst;
}

// The voxel part of a diff, accumulated per piece and merged (order-free).
struct VoxelPart {
  uint64_t compared = 0, differing = 0, onlyInA = 0, onlyInB = 0;
  std::array<VoxelKindDiff, kVoxelDiffKinds> kinds;
  std::optional<VoxelDiffExample> first;
};

}  // namespace

std::string describeVoxel(const VoxelValues& v) {
  if (!v.occupied) return "empty";
  std::string s = v.surface ? "surface" : "interior";
  s += " votes{";
  for (size_t i = 0; i < v.votes.size(); ++i)
    s += (i ? "," : "") + std::to_string(v.votes[i].classId) + ":" + std::to_string(v.votes[i].votes);
  s += "}";
  // Colours are floats: their own shortest text ("0.8749981", not 17 digits of a double).
  if (v.color)
    s += " color(" + shortestText(v.color->r) + "," + shortestText(v.color->g) + "," + shortestText(v.color->b) + ")";
  return s;
}

SceneDiff diffScenes(const Scene& a, const Scene& b, const SceneDiffOptions& o) {
  SceneDiff d;
  compareHeaders(a.header(), b.header(), o, d);
  d.voxelsA = a.occupiedCount();
  d.voxelsB = b.occupiedCount();

  std::vector<uint8_t> ids = a.classesPresent();
  for (uint8_t id : b.classesPresent()) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  const auto votesA = voteGridsFor(a, ids), votesB = voteGridsFor(b, ids);

  // Leaf origins of both occupancy trees (every active voxel sits in a leaf:
  // the readers expand tiles), in one sorted list.
  std::vector<openvdb::Coord> origins;
  origins.reserve(a.grids().occupancy->tree().leafCount() + b.grids().occupancy->tree().leafCount());
  for (auto l = a.grids().occupancy->tree().cbeginLeaf(); l; ++l) origins.push_back(l->origin());
  for (auto l = b.grids().occupancy->tree().cbeginLeaf(); l; ++l) origins.push_back(l->origin());
  std::sort(origins.begin(), origins.end());
  origins.erase(std::unique(origins.begin(), origins.end()), origins.end());

  // Fixed pieces; every merged quantity is a sum, a minimum or a maximum with
  // a total-order tie break, so the result does not depend on the split.
  const size_t pieces = std::min<size_t>(origins.size(), 256);
  std::vector<VoxelPart> parts(std::max<size_t>(pieces, 1));
  parallelPieces(origins.size(), o.threads, pieces, [&](size_t begin, size_t end, size_t p) {
    VoxelPart& part = parts[p];
    std::array<double, BoolLeaf::SIZE> voteDiff;
    for (size_t i = begin; i < end; ++i) {
      const SideLeaves la = probe(a, votesA, origins[i]), lb = probe(b, votesB, origins[i]);
      BoolLeaf::NodeMaskType either;
      if (la.occ) either = la.occ->getValueMask();
      if (lb.occ) either |= lb.occ->getValueMask();
      part.compared += either.countOn();
      // Most leaves of two similar scenes are equal: check whole leaves first.
      bool same = sameLeaf(la.occ, lb.occ) && sameLeaf(la.color, lb.color);
      for (size_t k = 0; same && k < ids.size(); ++k) same = sameLeaf(la.votes[k], lb.votes[k]);
      if (same) continue;
      // Vote differences class by class over each class's own voxels (most
      // voxels have votes for one or two classes, not for every class).
      std::fill(voteDiff.begin(), voteDiff.end(), 0.0);
      for (size_t k = 0; k < ids.size(); ++k) {
        const IntLeaf *va = la.votes[k], *vb = lb.votes[k];
        if (sameLeaf(va, vb)) continue;
        IntLeaf::NodeMaskType m;
        if (va) m = va->getValueMask();
        if (vb) m |= vb->getValueMask();
        for (auto it = m.beginOn(); it; ++it) {
          const openvdb::Index n = it.pos();
          const int64_t x = va && va->isValueOn(n) ? va->getValue(n) : 0;
          const int64_t y = vb && vb->isValueOn(n) ? vb->getValue(n) : 0;
          voteDiff[n] = std::max(voteDiff[n], double(x > y ? x - y : y - x));
        }
      }
      for (auto it = either.beginOn(); it; ++it) {
        // Magnitudes straight from the leaves; the voxel's values are built
        // only when it becomes a first or worst example (most differing
        // voxels of two scenes that differ everywhere never do).
        const openvdb::Index n = it.pos();
        const bool occA = la.occ && la.occ->isValueOn(n), occB = lb.occ && lb.occ->isValueOn(n);
        bool dOcc = false, dVotes = false, dColor = false, dSurface = false;
        double mOcc = 0, mVotes = 0, mColor = 0;
        if (occA != occB) {
          dOcc = true;
          const SideLeaves& l = occA ? la : lb;
          for (size_t k = 0; k < ids.size(); ++k)
            if (l.votes[k] && l.votes[k]->isValueOn(n)) mOcc += double(l.votes[k]->getValue(n));
        } else {
          mVotes = voteDiff[n];
          dVotes = mVotes > o.votesTolerance;
          const bool ca = la.color && la.color->isValueOn(n), cb = lb.color && lb.color->isValueOn(n);
          if (ca != cb) {
            mColor = 1.0, dColor = true;
          } else if (ca) {
            const openvdb::Vec3s& x = la.color->getValue(n);
            const openvdb::Vec3s& y = lb.color->getValue(n);
            for (int q = 0; q < 3; ++q) mColor = std::max(mColor, std::fabs(double(x[q]) - double(y[q])));
            dColor = mColor > o.colorTolerance;
          }
          dSurface = la.occ->getValue(n) != lb.occ->getValue(n);
        }
        if (!(dOcc || dVotes || dColor || dSurface)) continue;
        const openvdb::Coord c = BoolLeaf::offsetToLocalCoord(n) + origins[i];
        const Coord3 at{c.x(), c.y(), c.z()};
        std::optional<VoxelValues> va, vb;
        auto example = [&](double magnitude) {
          if (!va) va = valuesAt(la, ids, n), vb = valuesAt(lb, ids, n);
          return VoxelDiffExample{at, magnitude, *va, *vb};
        };
        auto consider = [&](VoxelDiffKind kind, double magnitude) {
          VoxelKindDiff& k = part.kinds[size_t(kind)];
          ++k.count;
          if (!k.first || orderKey(at) < orderKey(k.first->at)) k.first = example(magnitude);
          if (!k.worst || magnitude > k.worst->magnitude ||
              (magnitude == k.worst->magnitude && orderKey(at) < orderKey(k.worst->at)))
            k.worst = example(magnitude);
        };
        if (dOcc) {
          (occA ? part.onlyInA : part.onlyInB) += 1;
          consider(VoxelDiffKind::Occupancy, mOcc);
        }
        if (dVotes) consider(VoxelDiffKind::Votes, mVotes);
        if (dColor) consider(VoxelDiffKind::Color, mColor);
        if (dSurface) consider(VoxelDiffKind::Surface, 1.0);
        ++part.differing;
        if (!part.first || orderKey(at) < orderKey(part.first->at)) part.first = example(0);
      }
    }
  });
  for (const VoxelPart& part : parts) {
    d.voxelsCompared += part.compared;
    d.voxelsDiffering += part.differing;
    d.onlyInA += part.onlyInA;
    d.onlyInB += part.onlyInB;
    for (int k = 0; k < kVoxelDiffKinds; ++k) mergeKind(d.kinds[size_t(k)], part.kinds[size_t(k)]);
    if (part.first && (!d.first || orderKey(part.first->at) < orderKey(d.first->at))) d.first = part.first;
  }
  return d;
}

}  // namespace vox
