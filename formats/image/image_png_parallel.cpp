// A PNG writer that deflates slices of the image in parallel (pigz's scheme).
//
// Why not libpng: libpng drives one zlib stream, so a 1920x1080 RGBA16 render
// spends ~0.2 s in deflate on one core while the other idles. Here the
// filtered scanlines are cut into a fixed number of row slices; each is
// compressed as an independent raw deflate stream (Z_FULL_FLUSH, byte aligned,
// no final bit) and the slices are concatenated under one zlib header with the
// combined Adler-32. Any inflater reads it as one ordinary stream. The cut
// depends only on the image height, never on the thread count, so the bytes
// are identical at any thread count. Scanlines use the SUB filter, as writePng.
// Long runs of zero bytes (an atlas's empty texels) switch the slice's stream
// to zlib's Z_RLE strategy, where the cut again depends on the bytes only.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>

#include "formats/core/file_util.h"
#include "formats/image/image.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"

namespace vox {

namespace {

void put32(std::vector<uint8_t>& out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(uint8_t(v >> s));
}

void chunk(std::vector<uint8_t>& out, const char type[4], const uint8_t* data, size_t size) {
  put32(out, uint32_t(size));
  const size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  const uint32_t crc = uint32_t(crc32(0, out.data() + start, uInt(out.size() - start)));
  put32(out, crc);
}

}  // namespace

namespace {

// Both public writers: `palette` empty for gray/RGB(A), else an indexed-colour
// PNG (colour type 3) of the 1-channel 8-bit `image` with that PLTE.
// Quiet runs at least this long (bytes) are deflated with Z_RLE: a quarter
// of a 1024-texel RGBA8 row, long enough that a block boundary per switch
// costs well under 1% of what the run saves.
constexpr size_t kZeroRun = 4096;

void writeParallel(const Image& image, const std::vector<std::array<uint8_t, 3>>& palette, const std::string& path,
                   int zlibLevel, unsigned threads) {
  requirePngSides(image.width, image.height, path);
  if (image.type != SampleType::U8 && image.type != SampleType::U16)
    throw Error(ErrorKind::Internal, "writePngParallel: PNG holds 8 or 16-bit samples only");
  if (image.channels < 1 || image.channels > 4 || image.width == 0 || image.height == 0)
    throw Error(ErrorKind::Internal, "writePngParallel: bad image shape");
  const size_t sb = sampleBytes(image.type), bpp = image.channels * sb, rowBytes = image.width * bpp;
  const uint32_t H = image.height;
  // Slices of at least 64 rows, at most 16: enough for any core count we run on.
  const uint32_t slices = std::max<uint32_t>(1, std::min<uint32_t>(16, H / 64));
  std::vector<std::vector<uint8_t>> packed(slices);
  std::vector<uLong> adler(slices), inputBytes(slices);
  // Each slice writes its own outputs, so the slices run in any order.
  parallelForEach(slices, std::max(1u, threads), 1, [&](size_t s) {
    const uint32_t y0 = uint32_t(uint64_t(H) * s / slices), y1 = uint32_t(uint64_t(H) * (s + 1) / slices);
    // Filtered scanlines: filter byte 1 (SUB), samples big-endian.
    std::vector<uint8_t> raw(size_t(y1 - y0) * (rowBytes + 1));
    uint8_t* o = raw.data();
    std::vector<uint8_t> be(rowBytes);
    for (uint32_t y = y0; y < y1; ++y) {
      const uint8_t* src = image.pixels.data() + size_t(y) * rowBytes;
      if (sb == 2) {
        for (size_t i = 0; i < rowBytes; i += 2) {
          be[i] = src[i + 1];
          be[i + 1] = src[i];
        }
        src = be.data();
      }
      *o++ = 1;
      const size_t head = std::min(bpp, rowBytes);
      for (size_t i = 0; i < head; ++i) o[i] = src[i];
      for (size_t i = head; i < rowBytes; ++i) o[i] = uint8_t(src[i] - src[i - bpp]);
      o += rowBytes;
    }
    adler[s] = adler32(adler32(0, nullptr, 0), raw.data(), uInt(raw.size()));
    inputBytes[s] = uLong(raw.size());
    z_stream zs{};
    if (deflateInit2(&zs, zlibLevel, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
      throw Error(ErrorKind::Internal, "deflateInit2 failed");
    // Deflated through a small buffer and appended: a slice's output takes the
    // memory its compressed bytes need, not deflateBound's (the raw size and
    // more, zero-filled), which for a mostly empty atlas is 30 times as much.
    std::vector<uint8_t>& out = packed[s];
    uint8_t buffer[1 << 16];
    bool ok = true;
    auto drain = [&](int flush) {  // deflates what is in zs.next_in, then `flush`
      int r = Z_OK;
      do {
        zs.next_out = buffer;
        zs.avail_out = sizeof buffer;
        r = deflate(&zs, flush);
        out.insert(out.end(), buffer, buffer + (sizeof buffer - zs.avail_out));
      } while (r == Z_OK && (zs.avail_out == 0 || zs.avail_in > 0));
      return r;
    };
    // Long runs of zero bytes (empty texels; a row's filter byte does not
    // break a run) go through zlib's run-length strategy, the rest at the
    // level asked. Both code a zero run as the same longest matches at
    // distance 1, so the stream barely grows (a block boundary per switch),
    // but the level-6 matcher spends most of an atlas's deflate time hashing
    // every byte of its empty space. The cut depends on the bytes only.
    const size_t stride = rowBytes + 1, n = raw.size();
    // The end of the quiet run starting at i (i itself when raw[i] is not quiet).
    auto quietEnd = [&](size_t j) {
      while (j < n) {
        const size_t col = j % stride;
        if (col == 0) {
          ++j;
          continue;
        }
        const size_t rowEnd = std::min(n, j - col + stride);
        for (uint64_t w; j + 8 <= rowEnd; j += 8) {
          std::memcpy(&w, raw.data() + j, 8);
          if (w != 0) break;
        }
        while (j < rowEnd && raw[j] == 0) ++j;
        if (j < rowEnd) return j;
      }
      return n;
    };
    int strategy = Z_DEFAULT_STRATEGY;
    auto feed = [&](size_t begin, size_t end, int want) {
      if (begin == end) return;
      if (want != strategy) {
        int r = Z_BUF_ERROR;
        for (int tries = 0; tries < 4096 && r == Z_BUF_ERROR; ++tries) {
          zs.next_out = buffer;
          zs.avail_out = sizeof buffer;
          r = deflateParams(&zs, zlibLevel, want);
          out.insert(out.end(), buffer, buffer + (sizeof buffer - zs.avail_out));
        }
        ok = ok && r == Z_OK;
        strategy = want;
      }
      zs.next_in = raw.data() + begin;
      zs.avail_in = uInt(end - begin);
      const int r = drain(Z_NO_FLUSH);
      ok = ok && (r == Z_OK || r == Z_BUF_ERROR) && zs.avail_in == 0;
    };
    size_t content = 0;  // start of the content not yet fed
    for (size_t i = 0; i < n && zlibLevel > 0;) {
      const size_t e = quietEnd(i);
      if (e - i >= kZeroRun) {
        feed(content, i, Z_DEFAULT_STRATEGY);
        feed(i, e, Z_RLE);
        content = e;
      }
      i = std::max(e, i + 1);
    }
    feed(content, n, Z_DEFAULT_STRATEGY);
    const bool last = s + 1 == slices;
    const int r = drain(last ? Z_FINISH : Z_FULL_FLUSH);
    ok = ok && (last ? r == Z_STREAM_END : ((r == Z_OK || r == Z_BUF_ERROR) && zs.avail_in == 0));
    deflateEnd(&zs);
    if (!ok) throw Error(ErrorKind::Internal, "deflate failed on a PNG slice");
  });

  uLong a = adler[0];
  for (uint32_t s = 1; s < slices; ++s) a = adler32_combine(a, adler[s], z_off_t(inputBytes[s]));
  std::vector<uint8_t> z;
  const uint8_t cmf = 0x78;
  const uint8_t flevel = zlibLevel <= 1 ? 0 : zlibLevel <= 5 ? 1 : zlibLevel == 6 || zlibLevel < 0 ? 2 : 3;
  uint8_t flg = uint8_t(flevel << 6);
  flg = uint8_t(flg + (31 - (cmf * 256 + flg) % 31) % 31);
  size_t total = 6;
  for (const auto& p : packed) total += p.size();
  z.reserve(total);
  z.push_back(cmf);
  z.push_back(flg);
  for (auto& p : packed) {
    z.insert(z.end(), p.begin(), p.end());
    std::vector<uint8_t>().swap(p);
  }
  put32(z, uint32_t(a));

  std::vector<uint8_t> file;
  file.reserve(z.size() + 1024);
  const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  file.insert(file.end(), signature, signature + 8);
  std::vector<uint8_t> ihdr;
  put32(ihdr, image.width);
  put32(ihdr, image.height);
  static const uint8_t colorType[5] = {0, 0, 4, 2, 6};
  ihdr.push_back(uint8_t(sb * 8));
  ihdr.push_back(palette.empty() ? colorType[image.channels] : uint8_t(3));
  ihdr.push_back(0);
  ihdr.push_back(0);
  ihdr.push_back(0);
  chunk(file, "IHDR", ihdr.data(), ihdr.size());
  if (!palette.empty()) {
    std::vector<uint8_t> plte;
    for (const auto& c : palette) plte.insert(plte.end(), c.begin(), c.end());
    chunk(file, "PLTE", plte.data(), plte.size());
  }
  for (const auto& [key, value] : image.text) {
    std::vector<uint8_t> t(key.begin(), key.end());
    t.push_back(0);
    t.insert(t.end(), value.begin(), value.end());
    chunk(file, "tEXt", t.data(), t.size());
  }
  const size_t kIdatMax = size_t(1) << 22;
  for (size_t off = 0; off < z.size(); off += kIdatMax)
    chunk(file, "IDAT", z.data() + off, std::min(kIdatMax, z.size() - off));
  chunk(file, "IEND", nullptr, 0);

  writeFileBytes(path, file.data(), file.size());
}

}  // namespace

void writePngParallel(const Image& image, const std::string& path, int zlibLevel, unsigned threads) {
  writeParallel(image, {}, path, zlibLevel, threads);
}

void writeIndexedPngParallel(const Image& indices, const std::vector<std::array<uint8_t, 3>>& palette,
                             const std::string& path, int zlibLevel, unsigned threads) {
  if (indices.channels != 1 || indices.type != SampleType::U8 || palette.empty() || palette.size() > 256)
    throw Error(ErrorKind::Internal, "writeIndexedPngParallel: 1-channel 8-bit indices and 1..256 colours");
  writeParallel(indices, palette, path, zlibLevel, threads);
}

}  // namespace vox
