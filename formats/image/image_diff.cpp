#include "formats/image/image_diff.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "libvox/core/error.h"
#include "libvox/core/parallel.h"
#include "libvox/core/texel_formats.h"

namespace vox {

const char* imageVerdictName(ImageVerdict v) {
  switch (v) {
    case ImageVerdict::Pass: return "PASS";
    case ImageVerdict::Warn: return "WARNING";
    case ImageVerdict::Fail: return "FAILURE";
  }
  return "?";
}

double sampleFullScale(SampleType t) {
  switch (t) {
    case SampleType::U8: return 255.0;
    case SampleType::U16: return 65535.0;
    case SampleType::U32: return 4294967295.0;
    case SampleType::F16:
    case SampleType::F32: return 1.0;
  }
  return 1.0;
}

double sampleAt(const Image& img, uint32_t x, uint32_t y, uint32_t c) {
  const size_t i = (size_t(y) * img.width + x) * img.channels + c;
  const uint8_t* p = img.pixels.data();
  switch (img.type) {
    case SampleType::U8: return p[i];
    case SampleType::U16: return reinterpret_cast<const uint16_t*>(p)[i];
    case SampleType::U32: return reinterpret_cast<const uint32_t*>(p)[i];
    case SampleType::F16: return halfToFloat(reinterpret_cast<const uint16_t*>(p)[i]);
    case SampleType::F32: return reinterpret_cast<const float*>(p)[i];
  }
  return 0;
}

namespace {

bool hasAlpha(uint32_t channels) { return channels == 2 || channels == 4; }

// Raw samples of channel `c` of row `y`, as T (int64_t for the exact integer
// path, double otherwise, normalised when `normalise`).
template <typename T>
void channelRow(const Image& img, uint32_t y, uint32_t c, bool normalise, T* out) {
  const size_t base = size_t(y) * img.width * img.channels + c;
  const uint8_t* p = img.pixels.data();
  const double s = normalise ? 1.0 / sampleFullScale(img.type) : 1.0;
  const uint32_t n = img.channels;
  switch (img.type) {
    case SampleType::U8:
      for (uint32_t x = 0; x < img.width; ++x) out[x] = T(p[base + size_t(x) * n]);
      break;
    case SampleType::U16:
      for (uint32_t x = 0; x < img.width; ++x) out[x] = T(reinterpret_cast<const uint16_t*>(p)[base + size_t(x) * n]);
      break;
    case SampleType::U32:
      for (uint32_t x = 0; x < img.width; ++x) out[x] = T(reinterpret_cast<const uint32_t*>(p)[base + size_t(x) * n]);
      break;
    case SampleType::F16:
      for (uint32_t x = 0; x < img.width; ++x)
        out[x] = T(halfToFloat(reinterpret_cast<const uint16_t*>(p)[base + size_t(x) * n]));
      break;
    case SampleType::F32:
      for (uint32_t x = 0; x < img.width; ++x) out[x] = T(reinterpret_cast<const float*>(p)[base + size_t(x) * n]);
      break;
  }
  if constexpr (std::is_floating_point_v<T>)
    if (s != 1.0)
      for (uint32_t x = 0; x < img.width; ++x) out[x] *= s;
}

// Hit/miss of every pixel of row y.
void maskRow(const Image& img, uint32_t y, const std::array<uint8_t, 3>& background, bool nonZero,
             std::vector<uint8_t>& hit, std::vector<double>& tmp) {
  tmp.resize(img.width);
  hit.assign(img.width, 0);
  if (nonZero) {
    for (uint32_t c = 0; c < img.channels; ++c) {
      channelRow(img, y, c, true, tmp.data());
      for (uint32_t x = 0; x < img.width; ++x)
        if (tmp[x] != 0) hit[x] = 1;
    }
    return;
  }
  if (img.channels == 1 && (img.type == SampleType::F16 || img.type == SampleType::F32)) {
    // Depth images: a miss is +infinity.
    channelRow(img, y, 0, true, tmp.data());
    for (uint32_t x = 0; x < img.width; ++x) hit[x] = std::isfinite(tmp[x]);
    return;
  }
  if (hasAlpha(img.channels)) {
    channelRow(img, y, img.channels - 1, true, tmp.data());
    for (uint32_t x = 0; x < img.width; ++x) hit[x] = tmp[x] > 0;
    return;
  }
  for (uint32_t c = 0; c < img.channels; ++c) {
    channelRow(img, y, c, true, tmp.data());
    const double bg = background[std::min<uint32_t>(c, 2)] / 255.0;
    for (uint32_t x = 0; x < img.width; ++x)
      if (std::fabs(tmp[x] - bg) > 0.5 / 255.0) hit[x] = 1;
  }
}

struct MetricPart {
  uint64_t differing = 0, warn = 0, fail = 0, maskAgree = 0;
  uint64_t sumAbsInt = 0, sumSqInt = 0;  // exact path, raw units
  double sumAbs = 0, sumSq = 0;          // float path, normalised
  double maxError = -1;
  uint32_t maxX = 0, maxY = 0, maxC = 0;
  std::optional<std::array<uint32_t, 2>> first;
};

// SSIM of one window from its sums (raw units; `s` = full scale).
inline double windowSsim(double sx, double sy, double sxx, double syy, double sxy, double n, double s) {
  constexpr double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03;
  const double mx = sx / (n * s), my = sy / (n * s);
  const double vx = sxx / (n * s * s) - mx * mx;
  const double vy = syy / (n * s * s) - my * my;
  const double cxy = sxy / (n * s * s) - mx * my;
  return ((2 * mx * my + C1) * (2 * cxy + C2)) / ((mx * mx + my * my + C1) * (vx + vy + C2));
}

constexpr uint32_t kSsimWindow = 8;

// Sum of SSIM over the windows whose top row is in [r0, r1), channel c; rows
// of windows that touch no differing row are exactly 1 each and skipped.
template <typename T>
double ssimRows(const Image& a, const Image& b, uint32_t c, uint32_t r0, uint32_t r1, bool exact,
                const std::vector<uint8_t>& rowDiffers, const std::vector<uint32_t>& dirtyPrefix) {
  const uint32_t W = a.width, K = kSsimWindow, cols = W - K + 1;
  const double scale = exact ? sampleFullScale(a.type) : 1.0;
  std::vector<T> ra(W), rb(W);
  std::vector<T> sx(W), sy(W), sxx(W), syy(W), sxy(W);
  double total = 0;
  bool primed = false;  // column sums hold rows [y, y + K)
  auto addRow = [&](uint32_t y, int sign) {
    channelRow(a, y, c, !exact, ra.data());
    channelRow(b, y, c, !exact, rb.data());
    for (uint32_t x = 0; x < W; ++x) {
      const T va = ra[x], vb = rb[x];
      sx[x] += sign * va, sy[x] += sign * vb;
      sxx[x] += sign * va * va, syy[x] += sign * vb * vb, sxy[x] += sign * va * vb;
    }
  };
  (void)rowDiffers;
  for (uint32_t y = r0; y < r1; ++y) {
    const bool dirty = dirtyPrefix[y + K] - dirtyPrefix[y] > 0;
    if (!dirty) {
      total += double(cols);
      primed = false;
      continue;
    }
    if (!primed) {
      std::fill(sx.begin(), sx.end(), T(0)), std::fill(sy.begin(), sy.end(), T(0));
      std::fill(sxx.begin(), sxx.end(), T(0)), std::fill(syy.begin(), syy.end(), T(0));
      std::fill(sxy.begin(), sxy.end(), T(0));
      for (uint32_t k = 0; k < K; ++k) addRow(y + k, 1);
      primed = true;
    } else {
      addRow(y - 1, -1);
      addRow(y + K - 1, 1);
    }
    T hx = 0, hy = 0, hxx = 0, hyy = 0, hxy = 0;
    for (uint32_t x = 0; x < K; ++x) hx += sx[x], hy += sy[x], hxx += sxx[x], hyy += syy[x], hxy += sxy[x];
    for (uint32_t x = 0;; ++x) {
      total += windowSsim(double(hx), double(hy), double(hxx), double(hyy), double(hxy), double(K * K), scale);
      if (x + 1 == cols) break;
      hx += sx[x + K] - sx[x], hy += sy[x + K] - sy[x];
      hxx += sxx[x + K] - sxx[x], hyy += syy[x + K] - syy[x], hxy += sxy[x + K] - sxy[x];
    }
  }
  return total;
}

}  // namespace

ImageDiff diffImages(const Image& a, const Image& b, const ImageDiffOptions& o) {
  ImageDiff d;
  d.width = a.width, d.height = a.height;
  if (a.width != b.width || a.height != b.height) {
    d.incompatible = "sizes differ: " + std::to_string(a.width) + " x " + std::to_string(a.height) + " vs " +
                     std::to_string(b.width) + " x " + std::to_string(b.height);
    d.verdict = ImageVerdict::Fail;
    return d;
  }
  uint32_t channels = a.channels;
  if (a.channels != b.channels) {
    // RGB against RGBA (or gray against gray+alpha): the colour channels.
    const uint32_t lo = std::min(a.channels, b.channels), hi = std::max(a.channels, b.channels);
    if (hi != lo + 1 || !hasAlpha(hi)) {
      d.incompatible = "channel counts differ: " + std::to_string(a.channels) + " vs " + std::to_string(b.channels);
      d.verdict = ImageVerdict::Fail;
      return d;
    }
    channels = lo;
  }
  d.channels = channels;
  d.pixels = uint64_t(a.width) * a.height;
  const bool depth = a.channels == 1 && b.channels == 1 &&
                     (a.type == SampleType::F16 || a.type == SampleType::F32) &&
                     (b.type == SampleType::F16 || b.type == SampleType::F32);
  d.maskSource = o.maskNonZero ? "non-zero texels"
                 : depth       ? "finite depth"
                 : hasAlpha(a.channels) && hasAlpha(b.channels)     ? "alpha"
                 : !hasAlpha(a.channels) && !hasAlpha(b.channels) ? "background"
                 : hasAlpha(a.channels)                           ? "alpha (A), background (B)"
                                                                  : "background (A), alpha (B)";
  // Integer samples of one type: exact sums in raw units.
  const bool exact = a.type == b.type && (a.type == SampleType::U8 || a.type == SampleType::U16);
  const double scaleA = sampleFullScale(a.type), scaleB = sampleFullScale(b.type);

  const size_t pieces = std::min<size_t>(a.height, 64);
  std::vector<MetricPart> parts(std::max<size_t>(pieces, 1));
  std::vector<uint8_t> rowDiffers(a.height, 0);
  parallelPieces(a.height, o.threads, pieces, [&](size_t begin, size_t end, size_t p) {
    MetricPart& m = parts[p];
    std::vector<double> fa(a.width), fb(a.width), tmp;
    std::vector<int64_t> ia(a.width), ib(a.width);
    std::vector<double> pixErr(a.width);
    std::vector<uint8_t> hitA, hitB;
    for (size_t y = begin; y < end; ++y) {
      std::fill(pixErr.begin(), pixErr.end(), 0.0);
      bool rowDiff = false;
      for (uint32_t c = 0; c < channels; ++c) {
        if (exact) {
          channelRow(a, uint32_t(y), c, false, ia.data());
          channelRow(b, uint32_t(y), c, false, ib.data());
          for (uint32_t x = 0; x < a.width; ++x) {
            const uint64_t e = uint64_t(ia[x] > ib[x] ? ia[x] - ib[x] : ib[x] - ia[x]);
            if (!e) continue;
            m.sumAbsInt += e, m.sumSqInt += e * e;
            const double err = double(e) / scaleA;
            if (err > pixErr[x]) pixErr[x] = err;
            if (err > m.maxError) m.maxError = err, m.maxX = x, m.maxY = uint32_t(y), m.maxC = c;
            else if (err == m.maxError && std::pair(uint32_t(y), x) < std::pair(m.maxY, m.maxX))
              m.maxX = x, m.maxY = uint32_t(y), m.maxC = c;
          }
        } else {
          channelRow(a, uint32_t(y), c, true, fa.data());
          channelRow(b, uint32_t(y), c, true, fb.data());
          for (uint32_t x = 0; x < a.width; ++x) {
            // Equal values (infinities included) and NaN against NaN do not
            // differ; NaN against a number is an infinite error.
            if (fa[x] == fb[x] || (std::isnan(fa[x]) && std::isnan(fb[x]))) continue;
            const double err = std::fabs(fa[x] - fb[x]);
            const double e = std::isnan(err) ? std::numeric_limits<double>::infinity() : err;
            m.sumAbs += e, m.sumSq += e * e;
            if (e > pixErr[x]) pixErr[x] = e;
            if (e > m.maxError) m.maxError = e, m.maxX = x, m.maxY = uint32_t(y), m.maxC = c;
            else if (e == m.maxError && std::pair(uint32_t(y), x) < std::pair(m.maxY, m.maxX))
              m.maxX = x, m.maxY = uint32_t(y), m.maxC = c;
          }
        }
      }
      for (uint32_t x = 0; x < a.width; ++x) {
        const double e = pixErr[x];
        if (e > 0) {
          ++m.differing, rowDiff = true;
          if (!m.first) m.first = std::array<uint32_t, 2>{x, uint32_t(y)};
        }
        if (e > o.warnThreshold) ++m.warn;
        if (e > o.failThreshold) ++m.fail;
      }
      rowDiffers[y] = rowDiff;
      maskRow(a, uint32_t(y), o.background, o.maskNonZero, hitA, tmp);
      maskRow(b, uint32_t(y), o.background, o.maskNonZero, hitB, tmp);
      for (uint32_t x = 0; x < a.width; ++x) m.maskAgree += hitA[x] == hitB[x];
    }
  });
  uint64_t sumAbsInt = 0, sumSqInt = 0;
  double sumAbs = 0, sumSq = 0;
  double maxError = -1;
  for (const MetricPart& m : parts) {  // in piece (row) order: the first maximum wins
    d.pixelsDiffering += m.differing, d.warnPixels += m.warn, d.failPixels += m.fail, d.maskAgree += m.maskAgree;
    sumAbsInt += m.sumAbsInt, sumSqInt += m.sumSqInt, sumAbs += m.sumAbs, sumSq += m.sumSq;
    if (m.maxError > maxError) maxError = m.maxError, d.maxX = m.maxX, d.maxY = m.maxY, d.maxChannel = m.maxC;
    if (m.first && !d.firstDiffering) d.firstDiffering = m.first;
  }
  d.maxError = std::max(0.0, maxError);
  const double values = double(d.pixels) * channels;
  if (exact) {
    sumAbs = double(sumAbsInt) / scaleA;
    sumSq = double(sumSqInt) / (scaleA * scaleA);
  }
  (void)scaleB;
  d.meanError = values > 0 ? sumAbs / values : 0;
  d.mse = values > 0 ? sumSq / values : 0;
  d.rmsError = std::sqrt(d.mse);
  d.psnr = d.mse > 0 ? 10.0 * std::log10(1.0 / d.mse) : std::numeric_limits<double>::infinity();

  // SSIM over the colour channels.
  const uint32_t colorChannels = hasAlpha(channels) ? channels - 1 : channels;
  if (a.width >= kSsimWindow && a.height >= kSsimWindow && colorChannels > 0) {
    const uint32_t rows = a.height - kSsimWindow + 1;
    std::vector<uint32_t> dirtyPrefix(a.height + 1, 0);
    for (uint32_t y = 0; y < a.height; ++y) dirtyPrefix[y + 1] = dirtyPrefix[y] + rowDiffers[y];
    const size_t sp = std::min<size_t>(rows, 64);
    std::vector<double> sums(sp * colorChannels, 0.0);
    parallelPieces(size_t(rows) * colorChannels, o.threads, sp * colorChannels, [&](size_t, size_t, size_t p) {
      const uint32_t c = uint32_t(p / sp);
      const size_t q = p % sp;
      const uint32_t r0 = uint32_t(rows * q / sp), r1 = uint32_t(rows * (q + 1) / sp);
      sums[p] = exact ? ssimRows<int64_t>(a, b, c, r0, r1, true, rowDiffers, dirtyPrefix)
                      : ssimRows<double>(a, b, c, r0, r1, false, rowDiffers, dirtyPrefix);
    });
    double total = 0;
    for (double s : sums) total += s;
    d.ssim = total / (double(rows) * (a.width - kSsimWindow + 1) * colorChannels);
  }

  const double n = double(d.pixels);
  if (double(d.failPixels) > o.failPercent / 100.0 * n || d.maxError > o.hardFail)
    d.verdict = ImageVerdict::Fail;
  else if (double(d.warnPixels) > o.warnPercent / 100.0 * n || d.maxError > o.hardWarn)
    d.verdict = ImageVerdict::Warn;
  return d;
}

Image differenceImage(const Image& a, const Image& b, double scale, SampleType type) {
  if (a.width != b.width || a.height != b.height) throw Error(ErrorKind::Internal, "differenceImage: sizes differ");
  if (type != SampleType::U8 && type != SampleType::F32)
    throw Error(ErrorKind::Internal, "differenceImage: the difference is written as uint8 or float");
  Image out(a.width, a.height, 3, type);
  const uint32_t channels = std::min(a.channels, b.channels);
  const uint32_t colour = hasAlpha(channels) ? channels - 1 : channels;
  const bool alpha = hasAlpha(a.channels) && hasAlpha(b.channels);
  std::vector<double> fa(a.width), fb(a.width), row(size_t(a.width) * 3);
  // Equal samples differ by 0: inf - inf would be NaN.
  auto error = [scale](double x, double y) { return x == y ? 0.0 : scale * std::fabs(x - y); };
  for (uint32_t y = 0; y < a.height; ++y) {
    std::fill(row.begin(), row.end(), 0.0);
    for (uint32_t c = 0; c < colour; ++c) {
      channelRow(a, y, c, true, fa.data());
      channelRow(b, y, c, true, fb.data());
      for (uint32_t x = 0; x < a.width; ++x) {
        const double v = error(fa[x], fb[x]);
        if (colour == 1)
          row[3 * x] = row[3 * x + 1] = row[3 * x + 2] = v;
        else if (c < 3)
          row[3 * x + c] = v;
      }
    }
    if (alpha) {
      channelRow(a, y, a.channels - 1, true, fa.data());
      channelRow(b, y, b.channels - 1, true, fb.data());
      for (uint32_t x = 0; x < a.width; ++x) {
        const double v = error(fa[x], fb[x]);
        for (int k = 0; k < 3; ++k) row[3 * x + k] = std::max(row[3 * x + k], v);
      }
    }
    if (type == SampleType::U8) {
      uint8_t* o = out.row<uint8_t>(y);
      for (size_t i = 0; i < row.size(); ++i) o[i] = uint8_t(std::lround(255.0 * std::min(1.0, row[i])));
    } else {
      float* o = out.row<float>(y);
      for (size_t i = 0; i < row.size(); ++i) o[i] = float(row[i]);
    }
  }
  return out;
}

}  // namespace vox
