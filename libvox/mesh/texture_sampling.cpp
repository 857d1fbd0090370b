#include "libvox/mesh/texture_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <string>

#include "libvox/core/color.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"

namespace vox {

namespace {

double wrapCoord(double x, MeshTexture::Wrap mode) {
  switch (mode) {
    case MeshTexture::Wrap::ClampToEdge: return std::clamp(x, 0.0, 1.0);
    case MeshTexture::Wrap::MirroredRepeat: {
      double f = std::fmod(std::abs(x), 2.0);
      return f > 1.0 ? 2.0 - f : f;
    }
    default: return x - std::floor(x);
  }
}

/// srgb8ToLinear as a table here: the texel loop calls it 12 times a sample.
const std::array<float, 256>& srgbToLinearTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb8ToLinear(uint8_t(i));
    return t;
  }();
  return table;
}

/// Linear RGB at `p` from the spot's two rows (`row0` holds y0, `row1` y1),
/// bilinear unless `nearest`.
std::array<float, 3> sampleRows(const uint8_t* row0, const uint8_t* row1, const TexelSpot& p, bool nearest) {
  const std::array<float, 256>& lin = srgbToLinearTable();
  const size_t x0 = size_t(p.x0) * 4, x1 = size_t(p.x1) * 4;
  std::array<float, 3> r;
  if (nearest) {
    for (size_t k = 0; k < 3; ++k) r[k] = lin[row0[x0 + k]];
    return r;
  }
  const float fx = p.fx, fy = p.fy;
  for (size_t k = 0; k < 3; ++k) {
    const float a = lin[row0[x0 + k]], b = lin[row0[x1 + k]], c = lin[row1[x0 + k]], d = lin[row1[x1 + k]];
    r[k] = (a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy;
  }
  return r;
}

std::array<uint16_t, 3> sampledColor(const PieceLook& look, const std::array<float, 3>& texel) {
  return {uint16_t(q16(look.base[0] * texel[0])), uint16_t(q16(look.base[1] * texel[1])),
          uint16_t(q16(look.base[2] * texel[2]))};
}

void addToSum(ColorSum& sum, uint32_t votes, const std::array<uint16_t, 3>& c) {
  sum.r += votes * uint64_t(c[0]);
  sum.g += votes * uint64_t(c[1]);
  sum.b += votes * uint64_t(c[2]);
}

[[noreturn]] void tooManyInTile(const char* what) {
  throw Error(ErrorKind::Resource, std::string("a tile of the surface pass holds more ") + what + " than 32-bit indices can name" +
                                       "; bake a smaller region or a lower resolution");
}

}  // namespace

TextureSampling samplingOf(const MeshTexture& t) { return {t.width, t.height, t.wrapS, t.wrapT, t.nearest}; }

uint32_t ColorSumStore::add() {
  if (count_ >= UINT32_MAX) tooManyInTile("coloured voxels");
  if (count_ % kChunk == 0) chunks_.push_back(std::make_unique<ColorSum[]>(kChunk));  // zeroed: sums start at 0
  return uint32_t(count_++);
}

void TexturedPieces::addLook(const PieceLook& look) {
  if (looks_.size() >= UINT32_MAX) tooManyInTile("textured piece colours");
  looks_.push_back(look);
}

void TexturedPieces::addChunk() {
  if (count_ > UINT32_MAX - kChunk) tooManyInTile("textured pieces");  // indices stay below 2^32
  chunks_.push_back(std::make_unique_for_overwrite<TexturedPiece[]>(kChunk));  // no zeroing: each is written
}

TexelSpot texelSpot(const TextureSampling& tex, double s, double t) {
  const double x = wrapCoord(s, tex.wrapS) * tex.width - 0.5, y = wrapCoord(t, tex.wrapT) * tex.height - 0.5;
  // Wrapped texel index i and i + 1. For Repeat the wrapped coordinate is in
  // [0, 1], so i is in [-1, n]: a branch instead of two int64 divisions
  // (a piece each, during the geometry), the modulo for anything else.
  auto wrap2 = [](int64_t i, uint32_t n, MeshTexture::Wrap m, uint32_t& a, uint32_t& b) {
    if (m == MeshTexture::Wrap::Repeat) {
      if (i >= 0 && i < int64_t(n)) a = uint32_t(i);
      else if (i == -1) a = n - 1;
      else if (i == int64_t(n)) a = 0;
      else a = uint32_t(((i % n) + n) % n);
      b = a + 1 == n ? 0 : a + 1;
    } else {
      a = uint32_t(std::clamp<int64_t>(i, 0, int64_t(n) - 1));
      b = uint32_t(std::clamp<int64_t>(i + 1, 0, int64_t(n) - 1));
    }
  };
  TexelSpot p;
  if (tex.nearest) {
    wrap2(int64_t(std::floor(x + 0.5)), tex.width, tex.wrapS, p.x0, p.x1);
    wrap2(int64_t(std::floor(y + 0.5)), tex.height, tex.wrapT, p.y0, p.y1);
    p.fx = p.fy = 0;
  } else {
    const int64_t x0 = int64_t(std::floor(x)), y0 = int64_t(std::floor(y));
    p.fx = float(x - double(x0)), p.fy = float(y - double(y0));
    wrap2(x0, tex.width, tex.wrapS, p.x0, p.x1);
    wrap2(y0, tex.height, tex.wrapT, p.y0, p.y1);
  }
  return p;
}

void addTexturedPieces(const Mesh& mesh, const TexturedPieces& pieces, ColorSumStore& sums) {
  // The pieces come in the order their triangles were voxelized, their texels
  // scattered over textures far larger than the caches: each sample's rows are
  // prefetched kAhead pieces early, which hides most of the misses that
  // sampling during the geometry waited on.
  constexpr size_t kAhead = 16;
  auto rowsOf = [&](const TexturedPiece& p, const TexelSpot& spot, const uint8_t*& row0, const uint8_t*& row1) {
    const MeshTexture& tex = mesh.textures[pieces.look(p).texture];
    if (tex.width == 0 || tex.height == 0) return false;
    const size_t stride = size_t(tex.width) * 4;
    row0 = tex.rgba.data() + stride * spot.y0, row1 = tex.rgba.data() + stride * spot.y1;
    return true;
  };
  for (size_t i = 0; i < pieces.size(); ++i) {
    if (i + kAhead < pieces.size()) {
      const TexturedPiece& ahead = pieces[i + kAhead];
      const TexelSpot spot = unpackSpot(ahead.spot);
      const uint8_t *a, *b;
      if (rowsOf(ahead, spot, a, b)) {
        __builtin_prefetch(a + size_t(spot.x0) * 4);
        __builtin_prefetch(b + size_t(spot.x0) * 4);
      }
    }
    const TexturedPiece& p = pieces[i];
    const PieceLook& look = pieces.look(p);
    const TexelSpot spot = unpackSpot(p.spot);
    const uint8_t *row0, *row1;
    const std::array<float, 3> texel = rowsOf(p, spot, row0, row1)
                                           ? sampleRows(row0, row1, spot, mesh.textures[look.texture].nearest)
                                           : std::array<float, 3>{1, 1, 1};  // a texture without pixels is white
    addToSum(sums[p.sum], p.votes, sampledColor(look, texel));
  }
}

RowSampling::RowSampling(const Mesh& mesh, const TextureRowSource* source)
    : imageOf_(mesh.textures.size(), -1), firstBand_(1, 0) {
  sampling_.reserve(mesh.textures.size());
  for (const MeshTexture& t : mesh.textures) sampling_.push_back(samplingOf(t));
  if (!source) return;
  for (size_t i = 0; i < source->images(); ++i) {
    const std::array<uint32_t, 2> size = source->size(i);
    for (size_t t : source->texturesOf(i)) {
      imageOf_[t] = int(i);
      sampling_[t].width = size[0], sampling_[t].height = size[1];
    }
    firstBand_.push_back(firstBand_[i] + (size[1] + kTextureBandRows - 1) / kTextureBandRows);
  }
}

void sampleFromRows(const RowSampling& rows, const std::vector<RowPieces*>& tiles, TextureRowSource& source,
                    unsigned threads) {
  // Every tile's pieces by band, band by band, in tile order within a band:
  // a reference each (8 bytes; a sort of the pieces in place cost more in
  // cache misses than the memory it saved).
  const size_t nBands = rows.bands();
  std::vector<size_t> start(nBands + 1, 0);
  std::vector<std::vector<size_t>> cursor(tiles.size());
  for (size_t k = 0; k < tiles.size(); ++k)
    if (!tiles[k]->perBand.empty())
      for (size_t b = 0; b < nBands; ++b) start[b + 1] += tiles[k]->perBand[b];
  for (size_t b = 0; b < nBands; ++b) start[b + 1] += start[b];
  std::vector<size_t> next(start.begin(), start.end() - 1);
  for (size_t k = 0; k < tiles.size(); ++k) {
    if (tiles[k]->perBand.empty()) continue;
    cursor[k] = next;
    for (size_t b = 0; b < nBands; ++b) next[b] += tiles[k]->perBand[b];
  }
  struct Ref {
    uint32_t tile, piece;  // TexturedPieces stop below 2^32
  };
  const auto refs = std::make_unique_for_overwrite<Ref[]>(start[nBands]);
  parallelForEach(tiles.size(), threads, 1, [&](size_t k) {
    const TexturedPieces& pieces = tiles[k]->pieces;
    for (size_t i = 0; i < pieces.size(); ++i) {
      const TexturedPiece& p = pieces[i];
      refs[cursor[k][rows.band(pieces.look(p).texture, p.spot.y0)]++] = {uint32_t(k), uint32_t(i)};
    }
  });

  // Each image on its own task, top to bottom: the window holds band b's rows
  // and the row after it (a bilinear sample's second row), `top` row 0 (the
  // second row of samples on the last row of a Repeat-wrapped texture).
  const size_t nImages = source.images();
  std::vector<std::exception_ptr> errors(nImages);
  parallelForEach(nImages, threads, 1, [&](size_t image) {
    try {
      const std::unique_ptr<TextureRowReader> reader = source.open(image);
      const uint32_t w = reader->width(), h = reader->height();
      const std::array<uint32_t, 2> announced = source.size(image);
      if (w != announced[0] || h != announced[1])
        throw Error(ErrorKind::Internal, "texture image " + std::to_string(image) + " decodes to " +
                                             std::to_string(w) + " x " + std::to_string(h) + " pixels, its header said " +
                                             std::to_string(announced[0]) + " x " + std::to_string(announced[1]));
      constexpr uint32_t R = kTextureBandRows;
      const size_t stride = size_t(w) * 4;
      std::vector<uint8_t> window((R + 1) * stride), top(stride);
      reader->read(window.data(), std::min(h, R + 1));
      std::memcpy(top.data(), window.data(), stride);
      const uint32_t bands = (h + R - 1) / R, first = rows.firstBand(image);
      for (uint32_t b = 0; b < bands; ++b) {
        const uint32_t y = b * R;  // the image row in the window's first row
        // A band's pieces lie all over the tiles' chunks: each is prefetched
        // kAhead pieces early, where waiting on each miss was a third of the
        // sampling.
        constexpr size_t kAhead = 16;
        const size_t end = start[first + b + 1];
        for (size_t r = start[first + b]; r < end; ++r) {
          if (r + kAhead < end) __builtin_prefetch(&tiles[refs[r + kAhead].tile]->pieces[refs[r + kAhead].piece], 1);
          TexturedPieces& pieces = tiles[refs[r].tile]->pieces;
          TexturedPiece& p = pieces[refs[r].piece];
          const PieceLook& look = pieces.look(p);
          const TexelSpot spot = unpackSpot(p.spot);
          const uint8_t* row0 = window.data() + size_t(spot.y0 - y) * stride;
          const uint8_t* row1 = spot.y1 >= y ? window.data() + size_t(spot.y1 - y) * stride : top.data();
          p.sampled = sampledColor(look, sampleRows(row0, row1, spot, rows.sampling(look.texture).nearest));
        }
        if (b + 1 < bands) {  // rows y + R + 1 .. y + 2R after row y + R, which moves first
          std::memmove(window.data(), window.data() + size_t(R) * stride, stride);
          const uint32_t more = std::min(R, h - (y + R + 1));  // 0 when row y + R is the last
          if (more > 0) reader->read(window.data() + stride, more);
        }
      }
    } catch (...) {
      errors[image] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

void addSampledPieces(const TexturedPieces& pieces, ColorSumStore& sums) {
  for (size_t i = 0; i < pieces.size(); ++i) addToSum(sums[pieces[i].sum], pieces[i].votes, pieces[i].sampled);
}

}  // namespace vox
