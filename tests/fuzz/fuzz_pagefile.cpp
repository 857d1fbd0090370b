// libFuzzer target for the page file reader (formats/pagefile/pagefile.h), every
// layout of the table (formats/pagefile/layouts.h) and the metadata reader
// (formats/pagefile/pagefile_meta.h): any input must either open, verify and
// parse its metadata, or throw vox::Error; crashes, reads past the end (ASan),
// hangs and other exceptions are bugs.
// Build and run: scripts/fuzz_pagefile.sh [SECONDS]
#include <cstddef>
#include <cstdint>

#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/pagefile/svo_layout.h"
#include "libvox/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const vox::pagefile::Reader r = vox::pagefile::Reader::fromMemory(data, size, "fuzz.vpk");
    for (const auto& e : r.entries()) {
      const auto c = e.chunk();
      if (r.find(e.level, c[0], c[1], c[2]) != &e) __builtin_trap();  // lookup finds every entry
    }
    r.verify();
    vox::pagefile::readPageMeta(r.metaJson(), r.name());
    if (r.header().layout == vox::pagefile::Layout::Svo)  // the node/brick view checks the same payloads
      for (size_t i = 0; i < r.entries().size(); ++i) {
        const auto bricks = vox::pagefile::svoBricks(r, i);
        uint64_t leaves = 0;
        for (const auto& b : bricks) leaves += b.level == 0 ? b.voxels.size() : 0;
        if (leaves != r.entries()[i].occupied) __builtin_trap();  // verify() checked this
      }
  } catch (const vox::Error&) {
  }
  return 0;
}
