// libFuzzer target of class tables as stored in scene and page-file metadata
// (formats/scene/class_table_json.cpp, classTableFromJson), in both the stored
// and the hand-written form. A stored table the reader accepts, written again
// with classTableToJson, reads back as the same table.
#include <nlohmann/json.hpp>
#include <string>

#include "formats/scene/class_table_json.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(classtable) {
  const nlohmann::json doc = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) return 0;  // the callers parse the JSON and report its errors themselves
  const vox::ClassJsonForm form = size % 2 ? vox::ClassJsonForm::HandWritten : vox::ClassJsonForm::Stored;
  try {
    const vox::ClassTable table = vox::classTableFromJson(doc, form, "fuzz: metadata 'vox:classes'");
    const vox::ClassTable again = vox::classTableFromJson(vox::classTableToJson(table), vox::ClassJsonForm::Stored, "rewritten");
    VOX_FUZZ_REQUIRE(vox::classTableToJson(again) == vox::classTableToJson(table));
  } catch (const vox::Error&) {
  }
  return 0;
}
