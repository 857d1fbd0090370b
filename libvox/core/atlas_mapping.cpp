#include "libvox/core/atlas_mapping.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "libvox/core/error.h"

namespace vox {

AtlasLayout AtlasLayout::make(Dims d, uint32_t forcedT, uint32_t maxSide) {
  if (d.x == 0 || d.y == 0 || d.z == 0) throwUsage("atlas dims must be >= 1 on every axis, got " + toString(d));
  if (maxSide == 0) throwUsage("the largest atlas side must be >= 1", Setting::AtlasMaxSide);
  if (maxSide > kMaxAtlasSide)
    throwUsage("the largest atlas side " + std::to_string(maxSide) + " is past " + std::to_string(kMaxAtlasSide) +
                   ", the largest side a PNG or EXR image can have; lower the largest atlas side",
               Setting::AtlasMaxSide);
  if (d.x > maxSide)
    throwUsage("a tile is " + std::to_string(d.x) + " texels wide (X), more than the maximum side " +
                   std::to_string(maxSide) + "; raise the largest atlas side",
               Setting::AtlasMaxSide);
  if (d.y > maxSide)
    throwUsage("a tile is " + std::to_string(d.y) + " texels high (Y), more than the maximum side " +
                   std::to_string(maxSide) + "; raise the largest atlas side",
               Setting::AtlasMaxSide);
  const uint64_t maxT = std::min<uint64_t>(d.z, maxSide / d.x);  // T * X <= maxSide, and no empty columns
  const uint64_t maxR = maxSide / d.y;
  AtlasLayout L;
  L.dims = d;
  L.maxSide = maxSide;
  auto finish = [&](uint64_t T) {
    L.tilesPerRow = uint32_t(T);
    L.tileRows = uint32_t((uint64_t(d.z) + T - 1) / T);
    L.rowsPerLayer = uint32_t(std::min<uint64_t>(L.tileRows, maxR));
    L.layers = (L.tileRows + L.rowsPerLayer - 1) / L.rowsPerLayer;
    L.width = uint32_t(T * d.x);
    L.height = L.rowsPerLayer * d.y;
    return L;
  };
  if (forcedT) {
    if (forcedT > maxSide / d.x)
      throwUsage(std::to_string(forcedT) + " tiles per row make the atlas " + std::to_string(uint64_t(forcedT) * d.x) +
                     " texels wide, more than the maximum side " + std::to_string(maxSide),
                 Setting::AtlasTilesPerRow);
    return finish(forcedT);
  }
  // The best T by (area, skew, T). For a row count r = ceil(Z / T) the area
  // T * X * r * Y grows with T, so only the smallest T of each r can win:
  // T = ceil(Z / r). Those are visited from the first T that fits one layer
  // (r <= maxR) upward, jumping from one row count to the next, so the search
  // takes at most 2 sqrt(Z) steps (a scan of every T up to maxSide / X took
  // 14 s for Z = 2^32 - 1). 64-bit T: maxT may be 2^32 - 1.
  uint64_t best = 0, bestArea = 0, bestSkew = 0;
  for (uint64_t T = (uint64_t(d.z) + maxR - 1) / maxR; T <= maxT;) {
    const uint64_t rows = (uint64_t(d.z) + T - 1) / T;
    const uint64_t w = T * d.x, h = rows * d.y;
    const uint64_t area = w * h, skew = w > h ? w - h : h - w;
    if (!best || area < bestArea || (area == bestArea && skew < bestSkew)) best = T, bestArea = area, bestSkew = skew;
    if (rows == 1) break;
    T = (uint64_t(d.z) + rows - 2) / (rows - 1);  // the smallest T with fewer rows
  }
  return finish(best ? best : maxT);
}

std::string AtlasLayout::toJson() const {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "{\"dims\":[%u,%u,%u],\"tiles_per_row\":%u,\"rows_per_layer\":%u,\"layers\":%u,\"width\":%u,"
                "\"height\":%u,\"max_side\":%u}",
                dims.x, dims.y, dims.z, tilesPerRow, rowsPerLayer, layers, width, height, maxSide);
  return buf;
}

AtlasLayout AtlasLayout::fromJson(const std::string& json, const std::string& context) {
  // A fixed, flat format (written by toJson), parsed without a JSON library so
  // the light core stays dependency-free.
  auto field = [&](const char* name) -> const char* {
    const std::string key = std::string("\"") + name + "\":";
    const size_t at = json.find(key);
    if (at == std::string::npos) throwBadInput(context + ": atlas layout lacks '" + name + "'");
    return json.c_str() + at + key.size();
  };
  auto number = [&](const char*& p, const char* name) {
    char* end = nullptr;
    const unsigned long v = std::strtoul(p, &end, 10);
    if (end == p || v > 0xffffffffUL) throwBadInput(context + ": atlas layout field '" + name + "' is not a number");
    p = end;
    return uint32_t(v);
  };
  const char* p = field("dims");
  if (*p++ != '[') throwBadInput(context + ": atlas layout 'dims' must be [X,Y,Z]");
  Dims d;
  d.x = number(p, "dims");
  if (*p++ != ',') throwBadInput(context + ": atlas layout 'dims' must be [X,Y,Z]");
  d.y = number(p, "dims");
  if (*p++ != ',') throwBadInput(context + ": atlas layout 'dims' must be [X,Y,Z]");
  d.z = number(p, "dims");
  auto get = [&](const char* name) {
    const char* q = field(name);
    return number(q, name);
  };
  const uint32_t T = get("tiles_per_row"), maxSide = get("max_side");
  // 0 would ask make() for the default T: a written layout always names its T.
  if (T == 0) throwBadInput(context + ": atlas layout field 'tiles_per_row' must be >= 1");
  AtlasLayout L;
  try {
    L = make(d, T, maxSide);
  } catch (const Error& e) {
    throwBadInput(context + ": inconsistent atlas layout: " + e.what());
  }
  if (L.rowsPerLayer != get("rows_per_layer") || L.layers != get("layers") || L.width != get("width") ||
      L.height != get("height"))
    throwBadInput(context + ": inconsistent atlas layout (its sizes do not follow from dims, tiles_per_row, max_side)");
  return L;
}

}  // namespace vox
