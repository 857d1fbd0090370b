// Comparing two images the way OpenImageIO's idiff does, plus the image
// accuracy metrics block-renderer validations report (docs/diff.md).
//
// Samples are compared normalised, as idiff reads them: 8-, 16- and 32-bit
// unsigned samples are divided by 255, 65535 and 2^32 - 1; half and float
// samples are used as they are. For every pixel, the error of a channel is
// |a - b|; a pixel "fails" when one of its channels' errors is > failThreshold,
// "warns" when one is > warnThreshold (strictly greater, as idiff). The verdict:
//   Fail  if failing pixels > failPercent% of the pixels, or the largest error > hardFail;
//   Warn  else if warning pixels > warnPercent% of the pixels, or the largest error > hardWarn;
//   Pass  otherwise (and when the images are equal).
// Metrics over the compared channels (all of them; when only one image has an
// alpha channel, the colour channels):
//   mean error, MSE = mean of squared errors (idiff's RMS squared),
//   PSNR = 10 log10(1 / MSE) dB (peak 1.0; infinite for equal images),
//   max error with its pixel (first in row-major order) and channel,
//   SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) with an 8x8 uniform window
//     moved pixel by pixel over every position where it fits inside the image,
//     population (1/N) variances, C1 = (0.01)^2, C2 = (0.03)^2 on samples
//     normalised to [0, 1], computed per colour channel (R, G, B, or gray; alpha
//     excluded) and averaged over windows and channels; absent for images
//     smaller than 8x8,
//   mask agreement: the fraction of pixels where both images agree on hit/miss.
//     A pixel is a hit when its alpha is > 0 (images with alpha), otherwise
//     when its colour differs from the background colour (default the terrain
//     shading's sky, 135,207,235 in 8 bits: what shaded renders write for misses);
//     with maskNonZero (atlases), when any sample is non-zero; one-channel
//     half/float images (depth renders) when the sample is finite (a miss is +inf).
// Sums of integer samples are exact (64-bit integers), so results are the
// same at any thread count and match an independent float64 computation.
//
// Thread safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "formats/image/image.h"

namespace vox {

struct ImageDiffOptions {
  double failThreshold = 1e-6;
  double failPercent = 0;
  double hardFail = std::numeric_limits<double>::infinity();
  double warnThreshold = 1e-6;
  double warnPercent = 0;
  double hardWarn = std::numeric_limits<double>::infinity();
  /// The miss colour of images without alpha, 8-bit sRGB values.
  std::array<uint8_t, 3> background{135, 207, 235};
  /// Atlases and bitmaps: a texel is a hit when any of its samples is non-zero
  /// (empty voxels and padding are all zero; a summary's alpha, mrg, may be 0
  /// for an occupied voxel), instead of alpha / background.
  bool maskNonZero = false;
  unsigned threads = 0;
};

enum class ImageVerdict { Pass, Warn, Fail };
const char* imageVerdictName(ImageVerdict v);  // "PASS", "WARNING", "FAILURE"

struct ImageDiff {
  /// Set when the images cannot be compared pixel for pixel (sizes, channel
  /// counts): the verdict is then Fail and no metric is computed.
  std::string incompatible;
  uint32_t width = 0, height = 0;
  uint32_t channels = 0;  // compared channels
  uint64_t pixels = 0;
  uint64_t pixelsDiffering = 0;  // with any channel error > 0
  uint64_t warnPixels = 0, failPixels = 0;
  double meanError = 0, mse = 0, rmsError = 0, psnr = std::numeric_limits<double>::infinity();
  std::optional<double> ssim;
  double maxError = 0;
  uint32_t maxX = 0, maxY = 0, maxChannel = 0;
  std::optional<std::array<uint32_t, 2>> firstDiffering;  // (x, y), row-major first
  uint64_t maskAgree = 0;
  std::string maskSource;  // "alpha", "background", "alpha (A) / background (B)", ...
  ImageVerdict verdict = ImageVerdict::Pass;
  double maskAgreeFraction() const { return pixels ? double(maskAgree) / double(pixels) : 1.0; }
};

/// Compares `a` with `b` (see the top of this file).
ImageDiff diffImages(const Image& a, const Image& b, const ImageDiffOptions& options = {});

/// A sample of `image` as a double, raw (not normalised): pixel (x, y), channel c.
double sampleAt(const Image& image, uint32_t x, uint32_t y, uint32_t c);
/// What a sample is divided by to normalise it: 255, 65535, 2^32 - 1 or 1.
double sampleFullScale(SampleType t);

/// The difference image: RGB, each of R, G, B = scale * |a - b| of that
/// channel (normalised samples; gray images repeat their one channel), raised
/// to the alpha error where that is larger, so a pixel that differs only in
/// alpha still shows. Opaque, so every viewer shows it. `type` U8 (for PNG):
/// round(255 * min(1, value)); F32 (for EXR): the value itself, neither
/// rounded nor clamped. Equal samples (two infinities of depth misses too)
/// differ by 0. Requires compatible images (diffImages' `incompatible` empty).
Image differenceImage(const Image& a, const Image& b, double scale = 1.0, SampleType type = SampleType::U8);

}  // namespace vox
