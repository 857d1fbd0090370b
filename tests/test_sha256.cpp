#include <gtest/gtest.h>

#include "libvox/core/error.h"
#include "libvox/core/sha256.h"

TEST(Sha256, KnownVectors) {
  auto hex = [](const std::string& s) {
    vox::Sha256 h;
    h.update(s.data(), s.size());
    return h.hexDigest();
  };
  EXPECT_EQ(hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  // One million 'a' fed in odd-sized pieces crosses every buffering path.
  vox::Sha256 h;
  std::string chunk(997, 'a');
  size_t left = 1000000;
  while (left) {
    size_t n = std::min(left, chunk.size());
    h.update(chunk.data(), n);
    left -= n;
  }
  EXPECT_EQ(h.hexDigest(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// The SHA-NI rounds against the portable ones on pseudo-random data of every
// length around the block boundaries and a few long ones.
TEST(Sha256, HardwareMatchesPortable) {
  if (!vox::sha256Hardware()) GTEST_SKIP() << "this CPU has no SHA extensions: only the portable code runs";
  std::string data(200000, '\0');
  uint64_t x = 0x9e3779b97f4a7c15ULL;
  for (char& c : data) {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    c = char(x);
  }
  auto digest = [&](size_t n, bool portable) {
    if (portable) setenv("VOX_SHA256_PORTABLE", "1", 1);
    vox::Sha256 h;
    unsetenv("VOX_SHA256_PORTABLE");
    h.update(data.data(), n);
    return h.hexDigest();
  };
  for (size_t n : {size_t(0), size_t(1), size_t(55), size_t(56), size_t(63), size_t(64), size_t(65), size_t(127),
                   size_t(128), size_t(129), size_t(1000), size_t(4096), size_t(65537), size_t(200000)})
    EXPECT_EQ(digest(n, false), digest(n, true)) << n << " bytes";
}

// A file that is not there is worded as every input check words it.
TEST(Sha256, MissingFileSaysNoSuchFile) {
  try {
    vox::sha256File("/nonexistent-dir-of-vox/missing.obj");
    FAIL() << "no error";
  } catch (const vox::Error& e) {
    EXPECT_EQ(e.kind, vox::ErrorKind::BadInput);
    EXPECT_EQ(std::string(e.what()), "/nonexistent-dir-of-vox/missing.obj: no such file");
  }
}
