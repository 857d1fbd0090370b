// libFuzzer target of the --classes rules file (formats/mesh/classes_json.cpp,
// parseClassMapping, with the hand-written class entries of class_table_json.cpp).
#include <string>

#include "formats/mesh/classes_json.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(classes) {
  try {
    vox::parseClassMapping(std::string(reinterpret_cast<const char*>(data), size), "fuzz-classes.json");
  } catch (const vox::Error&) {
  }
  return 0;
}
