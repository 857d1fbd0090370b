#include "formats/pagefile/layouts.h"

#include "formats/pagefile/bricks_layout.h"
#include "formats/pagefile/columns_layout.h"
#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/svo_layout.h"
#include "libvox/core/error.h"

namespace vox::pagefile {

namespace {

// By ascending id, without gaps (the header's layout byte indexes it).
constexpr LayoutCodec kLayouts[] = {
    {Layout::Bricks, "bricks",
     "occupancy bitmap, then summary bytes, sRGB8 colour and surface bits of the occupied voxels in rank order",
     false, 0, &bricksSizeFromIndex, &encodeBricks, &decodeBricks},
    {Layout::Svo, "svo", "pointerless octree of 64-bit nodes over 8^3 bricks, mip bricks at inner nodes",  //
     true, kSvoFixedBytes, nullptr, &encodeSvo, &decodeSvo},
    {Layout::Columns, "columns",
     "z-innermost u32 solid and surface masks per column, mip ladder, summary bytes, colour offsets and colours of "
     "surface voxels",
     false, kColumnsFixedBytes, nullptr, &encodeColumns, &decodeColumns},
};

constexpr bool idsAreOneToN() {
  for (size_t i = 0; i < std::size(kLayouts); ++i)
    if (uint8_t(kLayouts[i].id) != i + 1) return false;
  return true;
}
static_assert(idsAreOneToN(), "the layout table lists ids 1, 2, 3, ... in order");

}  // namespace

std::span<const LayoutCodec> layoutTable() { return kLayouts; }

const LayoutCodec* findLayout(uint8_t id) {
  if (id < 1 || id > std::size(kLayouts)) return nullptr;
  return &kLayouts[id - 1];
}

const LayoutCodec* findLayout(std::string_view name) {
  for (const LayoutCodec& l : kLayouts)
    if (name == l.name) return &l;
  return nullptr;
}

const LayoutCodec& codecOf(Layout layout) {
  const LayoutCodec* l = findLayout(uint8_t(layout));
  if (!l) throw Error(ErrorKind::Internal, "page file: unknown layout " + std::to_string(int(layout)));
  return *l;
}

const char* layoutName(Layout layout) {
  const LayoutCodec* l = findLayout(uint8_t(layout));
  return l ? l->name : "unknown";
}

std::string layoutNameList() {
  std::string s;
  for (size_t i = 0; i < std::size(kLayouts); ++i)
    s += (i == 0 ? "" : i + 1 == std::size(kLayouts) ? " or " : ", ") + std::string(kLayouts[i].name);
  return s;
}

}  // namespace vox::pagefile
