// libFuzzer target of touched-set files (formats/image/touched_json.cpp,
// parseTouchedSet). A set the reader accepts must survive its writer: written
// and read again it is the same set.
#include <string>

#include "formats/image/touched_json.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(touched) {
  try {
    const vox::TouchedSet set = vox::parseTouchedSet(std::string(reinterpret_cast<const char*>(data), size), "fuzz-touched.json");
    VOX_FUZZ_REQUIRE(vox::parseTouchedSet(vox::touchedSetJson(set), "rewritten") == set);
  } catch (const vox::Error&) {
  }
  return 0;
}
