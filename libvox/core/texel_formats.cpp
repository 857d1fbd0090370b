#include "libvox/core/texel_formats.h"

#include <algorithm>
#include <atomic>
#include <cstring>

#include "libvox/core/parallel.h"

namespace vox {

const char* texelFormatName(TexelFormat f) {
  switch (f) {
    case TexelFormat::Rgba8: return "rgba8";
    case TexelFormat::Rgba16: return "rgba16";
    case TexelFormat::Rgba32ui: return "rgba32ui";
    case TexelFormat::Rgba16f: return "rgba16f";
    case TexelFormat::Rgba32f: return "rgba32f";
  }
  return "?";
}

std::optional<TexelFormat> parseTexelFormat(const std::string& n) {
  for (TexelFormat f : kTexelFormats)
    if (n == texelFormatName(f)) return f;
  return std::nullopt;
}

bool isFloatFormat(TexelFormat f) { return f == TexelFormat::Rgba16f || f == TexelFormat::Rgba32f; }

uint16_t floatToHalf(float value) {
  uint32_t x;
  std::memcpy(&x, &value, 4);
  const uint32_t sign = (x >> 16) & 0x8000u;
  x &= 0x7fffffffu;
  if (x >= 0x7f800000u) return uint16_t(sign | 0x7c00u | (x > 0x7f800000u ? 0x200u : 0));  // inf / nan
  if (x >= 0x477ff000u) return uint16_t(sign | 0x7c00u);  // rounds to infinity
  if (x < 0x38800000u) {  // subnormal half (or zero)
    if (x < 0x33000000u) return uint16_t(sign);
    const uint32_t e = x >> 23;
    uint32_t m = (x & 0x7fffffu) | 0x800000u;
    const uint32_t shift = 126 - e;  // 14 - (e - 112)
    const uint32_t half = m >> shift, rem = m & ((1u << shift) - 1), mid = 1u << (shift - 1);
    return uint16_t(sign | (half + (rem > mid || (rem == mid && (half & 1)))));
  }
  const uint32_t e = (x >> 23) - 112, m = x & 0x7fffffu;
  uint32_t h = (e << 10) | (m >> 13);
  const uint32_t rem = m & 0x1fffu;
  if (rem > 0x1000u || (rem == 0x1000u && (h & 1))) ++h;  // round to nearest even; may carry into the exponent
  return uint16_t(sign | h);
}

float halfToFloat(uint16_t h) {
  const uint32_t sign = uint32_t(h & 0x8000u) << 16;
  uint32_t e = (h >> 10) & 0x1f, m = h & 0x3ffu, bits;
  if (e == 0) {
    if (m == 0) {
      bits = sign;
    } else {  // subnormal: normalise
      e = 113;
      while (!(m & 0x400u)) m <<= 1, --e;
      bits = sign | (e << 23) | ((m & 0x3ffu) << 13);
    }
  } else if (e == 31) {
    bits = sign | 0x7f800000u | (m << 13);
  } else {
    bits = sign | ((e + 112) << 23) | (m << 13);
  }
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

uint64_t roundTrip(TexelFormat f, uint64_t v) {
  switch (f) {
    case TexelFormat::Rgba8: return uint8_t(v);
    case TexelFormat::Rgba16: return uint16_t(v);
    case TexelFormat::Rgba32ui: return uint32_t(v);
    case TexelFormat::Rgba16f: return uint64_t(halfToFloat(floatToHalf(float(v))));
    case TexelFormat::Rgba32f: return uint64_t(float(v));
  }
  return 0;
}

uint64_t maxExactInteger(TexelFormat f, unsigned threads) {
  const uint64_t limit = (uint64_t(1) << 32) + 1;  // one past the widest format
  if (f != TexelFormat::Rgba32ui) {
    for (uint64_t n = 0; n < limit; ++n)
      if (roundTrip(f, n) != n) return n - 1;
    return limit - 1;
  }
  // 2^32 checks: one range per thread; the answer is the smallest failure.
  const unsigned pieces = std::max(1u, threads);
  std::atomic<uint64_t> firstFailure{limit};
  parallelPieces(limit, pieces, pieces, [&](size_t begin, size_t end, size_t) {
    for (uint64_t n = begin; n < end; ++n)
      if (roundTrip(f, n) != n) {
        uint64_t cur = firstFailure.load();
        while (n < cur && !firstFailure.compare_exchange_weak(cur, n)) {
        }
        return;
      }
  });
  return firstFailure.load() - 1;
}

uint64_t documentedMaxExact(TexelFormat f) {
  switch (f) {
    case TexelFormat::Rgba8: return 255;
    case TexelFormat::Rgba16: return 65535;
    case TexelFormat::Rgba32ui: return 0xffffffffull;
    case TexelFormat::Rgba16f: return 2048;
    case TexelFormat::Rgba32f: return uint64_t(1) << 24;
  }
  return 0;
}

TexelFormat narrowestExactFormat(uint64_t maxCoordinate) {
  if (maxCoordinate <= 255) return TexelFormat::Rgba8;
  if (maxCoordinate <= 65535) return TexelFormat::Rgba16;
  return TexelFormat::Rgba32ui;
}

}  // namespace vox
