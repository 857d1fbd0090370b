#include "libvox/core/class_volume.h"

#include <algorithm>
#include <tuple>

#include "libvox/core/block_faces.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

// The sort key: brick row order of the block renderer (y, then z, then x).
auto orderKey(const Coord3& o) { return std::tuple(o.v, o.w, o.u); }

bool aligned(int32_t x) { return (x & (ClassVolume::kBrickSide - 1)) == 0; }

// Clears the voxels of `b` outside `box`; returns the voxels left.
uint32_t clipToBox(ClassVolume::Brick& b, const IndexBox& box) {
  const int n = ClassVolume::kBrickSide;
  const bool inside = b.origin.u >= box.min.u && b.origin.u + n - 1 <= box.max.u && b.origin.v >= box.min.v &&
                      b.origin.v + n - 1 <= box.max.v && b.origin.w >= box.min.w && b.origin.w + n - 1 <= box.max.w;
  uint32_t kept = 0;
  if (inside) {
    for (uint8_t c : b.classes) kept += c != 0;
    return kept;
  }
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int i = ClassVolume::voxelIndex(x, y, z);
        if (!b.classes[size_t(i)]) continue;
        const int32_t u = b.origin.u + x, v = b.origin.v + y, w = b.origin.w + z;
        if ((u >= box.min.u && u <= box.max.u && v >= box.min.v && v <= box.max.v && w >= box.min.w &&
                       w <= box.max.w)) {
          ++kept;
          continue;
        }
        b.classes[size_t(i)] = 0;
        b.colored[size_t(i) >> 6] &= ~(uint64_t(1) << (i & 63));
      }
  return kept;
}

}  // namespace

void ClassVolume::Brick::setColor(int i, RgbLinear c) {
  colors[size_t(i)] = c;
  colored[size_t(i) >> 6] |= uint64_t(1) << (i & 63);
}

ClassVolume::ClassVolume(IndexBox box, bool withColor) : box_(box), withColor_(withColor) {}

ClassVolume::Brick ClassVolume::makeBrick(Coord3 origin) const {
  Brick b;
  b.origin = origin;
  if (withColor_) b.colors.resize(kBrickVoxels);
  return b;
}

void ClassVolume::add(Brick brick) {
  if (finished_) throw Error(ErrorKind::Internal, "ClassVolume::add after finish()");
  bricks_.push_back(std::move(brick));
}

void ClassVolume::finish() {
  if (finished_) return;
  finished_ = true;
  std::vector<Brick> kept;
  kept.reserve(bricks_.size());
  occupied_ = 0;
  for (Brick& b : bricks_) {
    if (!aligned(b.origin.u) || !aligned(b.origin.v) || !aligned(b.origin.w))
      throw Error(ErrorKind::Internal, "ClassVolume: brick origin " + toString(b.origin) + " is not a multiple of 8");
    if (!withColor_) {
      b.colors.clear();
      b.colored.fill(0);
    }
    const uint32_t n = box_.empty() ? 0 : clipToBox(b, box_);
    if (n == 0) continue;
    occupied_ += n;
    kept.push_back(std::move(b));
  }
  std::sort(kept.begin(), kept.end(),
            [](const Brick& a, const Brick& b) { return orderKey(a.origin) < orderKey(b.origin); });
  for (size_t i = 1; i < kept.size(); ++i)
    if (kept[i - 1].origin == kept[i].origin)
      throw Error(ErrorKind::Internal, "ClassVolume: two bricks at " + toString(kept[i].origin));
  bricks_ = std::move(kept);
  for (Brick& b : bricks_)
    for (int f = 0; f < kBlockFaceCount; ++f) {
      const auto& n = kBlockFaces[size_t(f)].normal;
      const Brick* other = brickAt({b.origin.u + n[0] * kBrickSide, b.origin.v + n[1] * kBrickSide,
                                    b.origin.w + n[2] * kBrickSide});
      b.neighbours[size_t(f)] = other ? int32_t(other - bricks_.data()) : -1;
    }
}

const ClassVolume::Brick* ClassVolume::brickAt(Coord3 c) const {
  const Coord3 o{c.u & ~(kBrickSide - 1), c.v & ~(kBrickSide - 1), c.w & ~(kBrickSide - 1)};
  auto it = std::lower_bound(bricks_.begin(), bricks_.end(), orderKey(o),
                             [](const Brick& b, const auto& key) { return orderKey(b.origin) < key; });
  return it != bricks_.end() && it->origin == o ? &*it : nullptr;
}

void throwClassNotInTable(uint8_t classId, Coord3 at) {
  throwBadInput("class " + std::to_string(classId) + " (voxel " + toString(at) +
                ") has no entry in the class table, so it has no colour");
}

uint8_t ClassVolume::classAt(Coord3 c) const {
  const Brick* b = brickAt(c);
  if (!b) return 0;
  return b->classes[size_t(voxelIndex(c.u - b->origin.u, c.v - b->origin.v, c.w - b->origin.w))];
}

}  // namespace vox
