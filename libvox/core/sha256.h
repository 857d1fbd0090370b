// SHA-256 of a byte stream or a file, for scene provenance (`sources` in the
// scene metadata). Self-contained so the light core needs no crypto library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace vox {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, size_t bytes);
  std::string hexDigest();  // finalises; call once

 private:
  void block(const uint8_t* p);                // portable rounds, one 64-byte block
  void blocks(const uint8_t* p, size_t count);  // SHA-NI when the CPU has it, else block()
  uint32_t h_[8];
  uint8_t buf_[64];
  size_t bufLen_ = 0;
  uint64_t total_ = 0;
  bool hardware_;  // decided at construction (sha256Hardware())
};

/// True when a Sha256 constructed now uses the CPU's SHA extensions (set
/// VOX_SHA256_PORTABLE=1 in the environment to force the portable code).
bool sha256Hardware();

/// Hex SHA-256 of a file's bytes; throws vox::Error (BadInput) if it cannot be read.
std::string sha256File(const std::string& path, uint64_t* bytes = nullptr);

}  // namespace vox
