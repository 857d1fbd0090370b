// bloscLz4Frame against Blosc itself: the same bytes as blosc_compress_ctx
// for every shape of input the scene writer gives it and many it does not
// (sizes around every threshold, types of 1 to 300 bytes, data that
// compresses, that does not, and that only partly does; outputs too small),
// and frames Blosc decompresses back to the input.
#include <gtest/gtest.h>

#include <blosc.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "formats/scene/blosc_lz4_frame.h"

namespace {

enum class Content { Zeros, Random, SmallInts, Colors, Runs, HalfRandom };

std::vector<uint8_t> makeInput(Content c, size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> v(n, 0);
  switch (c) {
    case Content::Zeros: break;
    case Content::Random:
      for (auto& b : v) b = uint8_t(rng());
      break;
    case Content::SmallInts:  // vote counts: int32 below a few thousand
      for (size_t i = 0; i + 4 <= n; i += 4) {
        const uint32_t x = rng() % 3000;
        std::memcpy(&v[i], &x, 4);
      }
      break;
    case Content::Colors:  // linear RGB floats in [0, 1], a few distinct
      for (size_t i = 0; i + 4 <= n; i += 4) {
        const float x = float(rng() % 7) / 6.0f;
        std::memcpy(&v[i], &x, 4);
      }
      break;
    case Content::Runs:
      for (size_t i = 0; i < n; ++i) v[i] = uint8_t((i / 37) % 5);
      break;
    case Content::HalfRandom:  // one stream compresses, the others do not
      for (size_t i = 0; i < n; ++i) v[i] = (i % 4 == 0) ? 7 : uint8_t(rng());
      break;
  }
  return v;
}

void expectSameFrame(const std::vector<uint8_t>& in, size_t typeSize, size_t destSize, const std::string& what) {
  std::vector<uint8_t> ours(destSize + 64, 0xAB), theirs(destSize + 64, 0xAB);
  const size_t n = vox::bloscLz4Frame(in.data(), in.size(), typeSize, ours.data(), destSize);
  const int m = blosc_compress_ctx(9, BLOSC_SHUFFLE, typeSize, in.size(), in.data(), theirs.data(), destSize,
                                   BLOSC_LZ4_COMPNAME, in.size(), 1);
  ASSERT_EQ(n, size_t(m > 0 ? m : 0)) << what;
  if (m <= 0) return;
  ASSERT_LE(n, destSize) << what;
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(ours[i], theirs[i]) << what << ": first difference at byte " << i << " of " << n;
  for (size_t i = destSize; i < ours.size(); ++i) ASSERT_EQ(ours[i], 0xAB) << what << ": wrote past destSize";
  // And the frame reads back.
  std::vector<uint8_t> back(in.size() + 1);
  ASSERT_EQ(blosc_decompress_ctx(ours.data(), back.data(), back.size(), 1), int(in.size())) << what;
  if (!in.empty()) ASSERT_EQ(0, std::memcmp(back.data(), in.data(), in.size())) << what;
}

}  // namespace

TEST(BloscLz4Frame, SameBytesAsBloscForTheScenesLeaves) {
  // The scene writer's calls: int32 votes, vec3s colours and bool masks' sizes
  // for 0..512 active voxels, typeSize 4, room for the whole input plus the header.
  const Content contents[] = {Content::Zeros, Content::Random, Content::SmallInts, Content::Colors, Content::Runs,
                              Content::HalfRandom};
  for (Content c : contents)
    for (size_t voxels = 0; voxels <= 512; ++voxels)
      for (size_t perVoxel : {size_t(4), size_t(12)}) {
        const size_t bytes = voxels * perVoxel;
        const auto in = makeInput(c, bytes, uint32_t(voxels * 131 + perVoxel));
        expectSameFrame(in, 4, bytes + vox::kBloscFrameOverhead,
                        "content " + std::to_string(int(c)) + ", " + std::to_string(bytes) + " bytes");
      }
}

TEST(BloscLz4Frame, SameBytesAsBloscForOtherTypesAndSizes) {
  const size_t typeSizes[] = {1, 2, 3, 4, 8, 12, 16, 17, 255, 256, 300};
  const size_t sizes[] = {0, 1, 3, 4, 5, 100, 127, 128, 129, 511, 512, 513, 2047, 2048, 2049, 4095, 4096, 4100, 6143,
                          6144, 65535, 65536, 70001, 262144, 1 << 20, (1 << 20) + 12, 3 * (1 << 20) + 5};
  const Content contents[] = {Content::Zeros, Content::Random, Content::SmallInts, Content::Runs, Content::HalfRandom};
  for (size_t t : typeSizes)
    for (size_t s : sizes)
      for (Content c : contents) {
        const auto in = makeInput(c, s, uint32_t(s * 7 + t));
        expectSameFrame(in, t, s + vox::kBloscFrameOverhead,
                        "type " + std::to_string(t) + ", content " + std::to_string(int(c)) + ", " + std::to_string(s) +
                            " bytes");
      }
}

TEST(BloscLz4Frame, SameAnswerAsBloscWhenTheOutputIsShort) {
  // Room for less than the stored frame: both compress into what there is,
  // or both give up (0).
  const Content contents[] = {Content::Zeros, Content::Random, Content::SmallInts, Content::HalfRandom};
  for (Content c : contents)
    for (size_t s : {size_t(0), size_t(50), size_t(200), size_t(2048), size_t(6144)})
      for (size_t room : {size_t(0), size_t(15), size_t(16), size_t(17), size_t(40), s / 2, s / 4 * 3, s + 15}) {
        const auto in = makeInput(c, s, uint32_t(s + room));
        expectSameFrame(in, 4, room,
                        "content " + std::to_string(int(c)) + ", " + std::to_string(s) + " bytes into " +
                            std::to_string(room));
      }
}
