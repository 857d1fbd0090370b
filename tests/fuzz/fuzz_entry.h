// The entry point of a libFuzzer target, and of its regression replay.
//
// A fuzz build (scripts/fuzz_all.sh, clang -fsanitize=fuzzer) makes
// VOX_FUZZ_TARGET(name) libFuzzer's LLVMFuzzerTestOneInput. The unit tests
// (tests/test_fuzz_regressions.cpp) compile the same file with
// VOX_FUZZ_REPLAY defined, which makes it `int voxFuzz_<name>(data, size)`,
// and run every file of tests/fuzz/regressions/<name>/ through it, so each
// crash the fuzzer found stays fixed without clang.
//
// A target accepts any input that parses or throws vox::Error; anything else
// (a crash, a sanitizer report, another exception, a broken promise the target
// checks with VOX_FUZZ_REQUIRE) is a failure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>

#ifdef VOX_FUZZ_REPLAY
#define VOX_FUZZ_TARGET(name) int voxFuzz_##name(const uint8_t* data, size_t size)
#else
#define VOX_FUZZ_TARGET(name) extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
#endif

/// A promise of the parser that the input broke: reported and aborted (a
/// fuzzer finding; in the replay, a crashed test).
#define VOX_FUZZ_REQUIRE(cond)                                                  \
  do {                                                                          \
    if (!(cond)) {                                                              \
      std::fprintf(stderr, "%s:%d: fuzz check failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                             \
    }                                                                           \
  } while (0)
