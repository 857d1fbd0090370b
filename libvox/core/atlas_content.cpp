#include "libvox/core/atlas_content.h"
#include "libvox/core/color.h"

#include <algorithm>
#include <cmath>

#include "libvox/core/summary_bytes.h"

namespace vox {

const char* atlasContentName(AtlasContent c) {
  switch (c) {
    case AtlasContent::Summary: return "summary";
    case AtlasContent::Identity: return "identity";
    case AtlasContent::Color: return "color";
    case AtlasContent::Votes: return "votes";
    case AtlasContent::Occupancy: return "occupancy";
    case AtlasContent::Occupancy2: return "occupancy2";
  }
  return "?";
}

std::optional<AtlasContent> parseAtlasContent(const std::string& n) {
  for (AtlasContent c : {AtlasContent::Summary, AtlasContent::Identity, AtlasContent::Color, AtlasContent::Votes,
                         AtlasContent::Occupancy, AtlasContent::Occupancy2})
    if (n == atlasContentName(c)) return c;
  return std::nullopt;
}

std::array<uint64_t, 4> atlasTexel(AtlasContent content, const VoxelView* v, TexelFormat identityFormat,
                                   uint8_t classId) {
  if (!v) return {0, 0, 0, 0};
  switch (content) {
    case AtlasContent::Summary: {
      const SummaryTexel s = summarize(v->votes);
      return {s.cls, s.conf, s.obs, s.mrg};
    }
    case AtlasContent::Identity: {
      const uint64_t one = identityFormat == TexelFormat::Rgba8    ? 255
                           : identityFormat == TexelFormat::Rgba16 ? 65535
                           : identityFormat == TexelFormat::Rgba32ui ? 0xffffffffull
                                                                     : 1;
      return {uint64_t(v->at.u), uint64_t(v->at.v), uint64_t(v->at.w), one};
    }
    case AtlasContent::Color:
      if (!v->color) return {0, 0, 0, 0};
      return {linearToSrgb8(v->color->r), linearToSrgb8(v->color->g), linearToSrgb8(v->color->b), 255};
    case AtlasContent::Votes:
      for (const ClassVotes& c : v->votes)
        if (c.classId == classId) return {c.votes, 0, 0, 0};
      return {0, 0, 0, 0};
    case AtlasContent::Occupancy:
    case AtlasContent::Occupancy2: return {1, 0, 0, 0};
  }
  return {0, 0, 0, 0};
}

}  // namespace vox
