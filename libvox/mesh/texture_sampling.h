// The colour of textured surface pieces: where a piece samples its texture
// (the texel spot, computed while the geometry is voxelized), the bilinear or
// nearest sample, and the two ways its texels are taken:
//  * from a texture whose pixels are in the mesh (addTexturedPieces), by the
//    tile that made the pieces, when its geometry is done;
//  * from images read row by row after the whole geometry
//    (sampleFromRows, libvox/mesh/texture_rows.h): the pieces are sorted into
//    bands of rows, each image is read top to bottom once on its own task,
//    and a band's pieces take their texels while it is in memory, so no image
//    is ever held whole.
// A piece's colour is added to its voxel's integer sums, so the order pieces
// are sampled in does not change a bit of the result: both ways give the
// colours a bake with every image decoded first gives.
//
// Internal to libvox/mesh (voxelize.cpp's surface pass). Thread-safety: as
// each function says.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "libvox/mesh/mesh.h"
#include "libvox/mesh/texture_rows.h"

namespace vox {

/// A surface voxel's colour sums: vote-weighted 16-bit fixed-point channels.
struct ColorSum {
  uint64_t r = 0, g = 0, b = 0, w = 0;
};

/// How a texture is sampled; its width and height are those of its image,
/// which for a texture read by rows comes from the image's header.
struct TextureSampling {
  uint32_t width = 0, height = 0;  // 0: no pixels (samples white)
  MeshTexture::Wrap wrapS = MeshTexture::Wrap::Repeat, wrapT = MeshTexture::Wrap::Repeat;
  bool nearest = false;
};
TextureSampling samplingOf(const MeshTexture& t);

/// Where a texture is sampled: the texels' columns x0/x1 and rows y0/y1 and
/// the bilinear weights; nearest samples use (x0, y0) alone. y1 is y0, y0 + 1,
/// or row 0 (Repeat wrapping at the bottom).
struct TexelSpot {
  uint32_t x0, x1, y0, y1;  // trivial (no initialisers): a member of TexturedPiece's union
  float fx, fy;
};
/// The spot of texture coordinates (s, t) in glTF conventions (t = 0 at the
/// top row), wrapped as the sampler says. `tex` must have pixels (width > 0).
TexelSpot texelSpot(const TextureSampling& tex, double s, double t);

/// A colour channel in [0, 1] as the 16-bit fixed point the sums add
/// (clamped; NaN is 0). Inline: the surface pass calls it three times for
/// every coloured piece, which out of line cost a coloured bake about 1%.
inline uint64_t q16(float x) {
  // std::lround without its libm call: for a float v in [0, 65535], v + 0.5
  // is exact in double, so its truncation is lround's round-half-away-from-
  // zero (the same value for every float in [0, 1], checked exhaustively).
  const float v = std::clamp(x, 0.0f, 1.0f) * 65535.0f;
  if (!(v >= 0.0f)) return 0;
  return uint64_t(double(v) + 0.5);
}

/// A tile's colour sums, by slot, in chunks that never move (the pieces
/// below name their sum by slot: 4 bytes where a pointer took 8).
class ColorSumStore {
 public:
  static constexpr size_t kChunk = 4096;
  /// A new sum, zero; its slot (below 2^32 - 1). Throws vox::Error
  /// (Resource) past that many sums in one tile.
  uint32_t add();
  ColorSum& operator[](uint32_t slot) { return chunks_[slot / kChunk][slot % kChunk]; }
  const ColorSum& operator[](uint32_t slot) const { return chunks_[slot / kChunk][slot % kChunk]; }

 private:
  std::vector<std::unique_ptr<ColorSum[]>> chunks_;
  size_t count_ = 0;
};

/// What a textured piece's colour is before its texel: the base colour
/// (base colour factor x vertex colour) and the texture. Pieces of one
/// triangle without vertex colours share one.
struct PieceLook {
  std::array<float, 3> base;
  uint32_t texture;
  bool operator==(const PieceLook&) const = default;
};

/// A TexelSpot in 17 bytes: x1 and y1 are always x0 + 1, 0 or x0 (y likewise),
/// so a 2-bit code each stands in for them.
struct PackedSpot {
  uint32_t x0, y0;
  float fx, fy;
  uint8_t next;  // bits 0-1: x1, bits 2-3: y1; 0: +1, 1: 0, 2: the same
};
inline PackedSpot packSpot(const TexelSpot& s) {
  auto code = [](uint32_t a, uint32_t b) { return uint8_t(b == a + 1 ? 0 : b == 0 ? 1 : 2); };  // texelSpot gives no other
  return {s.x0, s.y0, s.fx, s.fy, uint8_t(code(s.x0, s.x1) | code(s.y0, s.y1) << 2)};
}
inline TexelSpot unpackSpot(const PackedSpot& p) {
  auto next = [](uint32_t a, unsigned code) { return code == 0 ? a + 1 : code == 1 ? 0 : a; };
  return {p.x0, next(p.x0, p.next & 3u), p.y0, next(p.y0, (p.next >> 2) & 3u), p.fx, p.fy};
}

/// A piece of a textured triangle whose texel is added to its voxel's sum
/// after its tile's geometry: its sum's slot, its votes, its look and where
/// it samples; once sampled by rows, `sampled` holds q16 of base x texel per
/// channel in place of the spot. 32 bytes (56 before the slots, looks and
/// packed spots): the textured benchmark model makes 520 k of them, all
/// fresh memory, which costs more on a VM than the sampling does.
struct TexturedPiece {
  uint32_t sum;
  uint32_t votes;
  uint32_t look;
  union {
    PackedSpot spot;
    std::array<uint16_t, 3> sampled;
  };
};
static_assert(sizeof(TexturedPiece) == 32);

/// A tile's textured pieces, in chunks that are never copied (a vector's
/// growth copied the pieces and faulted their memory in about twice over),
/// and their looks.
class TexturedPieces {
 public:
  static constexpr size_t kChunk = 4096;
  /// Appends a piece; its look is stored once for a run of pieces that share
  /// it. Throws vox::Error (Resource) when a tile's pieces or looks would
  /// outgrow 32-bit indices.
  void push(uint32_t sum, uint32_t votes, const PieceLook& look, const TexelSpot& spot) {
    if (looks_.empty() || !(looks_.back() == look)) addLook(look);
    if (count_ % kChunk == 0) addChunk();
    TexturedPiece& p = chunks_.back()[count_++ % kChunk];
    p.sum = sum, p.votes = votes, p.look = uint32_t(looks_.size() - 1);
    p.spot = packSpot(spot);
  }
  size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  TexturedPiece& operator[](size_t i) { return chunks_[i / kChunk][i % kChunk]; }
  const TexturedPiece& operator[](size_t i) const { return chunks_[i / kChunk][i % kChunk]; }
  const PieceLook& look(const TexturedPiece& p) const { return looks_[p.look]; }
  void clear() { *this = TexturedPieces(); }

 private:
  void addLook(const PieceLook& look);
  void addChunk();
  std::vector<std::unique_ptr<TexturedPiece[]>> chunks_;
  std::vector<PieceLook> looks_;
  size_t count_ = 0;
};

/// Adds each piece's colour (base x texel of its look's mesh texture, white
/// where the texture has no pixels) to its sum in `sums`, in order. Pieces of
/// textures larger than the caches are scattered over them: each sample's
/// rows are prefetched a few pieces early. Call on the thread that owns the sums.
void addTexturedPieces(const Mesh& mesh, const TexturedPieces& pieces, ColorSumStore& sums);

/// How the bake samples each mesh texture (width and height from the images'
/// headers for the textures of `source`), which textures are read by rows,
/// and the bands of rows their pieces are sorted into. Without a source every
/// texture samples its pixels in the mesh. Read-only after construction.
class RowSampling {
 public:
  RowSampling(const Mesh& mesh, const TextureRowSource* source);
  const TextureSampling& sampling(uint32_t texture) const { return sampling_[texture]; }
  /// The texture's image in the source, or -1: its pixels are in the mesh.
  int imageOf(uint32_t texture) const { return imageOf_[texture]; }
  /// The bucket of a piece sampling row y0 of texture read by rows.
  uint32_t band(uint32_t texture, uint32_t y0) const {
    return firstBand_[size_t(imageOf_[texture])] + y0 / kTextureBandRows;
  }
  uint32_t firstBand(size_t image) const { return firstBand_[image]; }
  size_t bands() const { return firstBand_.back(); }

 private:
  std::vector<TextureSampling> sampling_;
  std::vector<int> imageOf_;         // per texture
  std::vector<uint32_t> firstBand_;  // per image, and the total at the end
};

/// A tile's pieces of textures read by rows, and how many fall in each band.
struct RowPieces {
  TexturedPieces pieces;
  std::vector<uint32_t> perBand;  // RowSampling::bands() entries once a piece is in
  void push(uint32_t sum, uint32_t votes, const PieceLook& look, const TexelSpot& spot, uint32_t band,
            size_t bands) {
    if (perBand.empty()) perBand.assign(bands, 0);
    ++perBand[band];
    pieces.push(sum, votes, look, spot);
  }
};

/// Samples the pieces of textures read by rows, `tiles` (in tile order; each
/// piece gets `sampled`). Every image of `source` is read once, whole (an
/// image no piece samples too: an undecodable image is an error whatever the
/// bake needs), one image per task on up to `threads` workers, with a band
/// of rows and row 0 in memory at a time. Then call addSampledPieces per
/// tile. Throws the error of the first image, in index order, that cannot
/// be read.
void sampleFromRows(const RowSampling& rows, const std::vector<RowPieces*>& tiles, TextureRowSource& source,
                    unsigned threads);

/// Adds the colours sampleFromRows gave `pieces` to their sums in `sums`.
/// Call on the thread that owns the sums.
void addSampledPieces(const TexturedPieces& pieces, ColorSumStore& sums);

}  // namespace vox
