// Parsing the JSON documents vox reads: camera files, block maps, fuse views
// files, class mappings, touched sets, reports and sidecars, and the JSON
// vox keeps in file metadata. JSON (RFC 8259) leaves an object that names a
// key twice to the reader, and nlohmann::json keeps the last value silently:
// a camera file with two "fov" keys rendered with the second, whatever its
// author meant. Every reader goes through parseJsonInput, which refuses such
// an object, naming the file, the key and the object ("cams.json: duplicate
// key "fov" in cameras[1]"). glTF forbids duplicate keys outright.
// Thread-safety: pure functions.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace vox {

/// Parses `text` as nlohmann::json::parse does: a syntax error (or a number
/// past double's range) throws nlohmann::json::exception, which each reader
/// words as "not valid JSON" in its own way. An object that names one key
/// twice throws vox::Error (BadInput): "NAME: duplicate key "K" in OBJECT:
/// JSON keeps only one of the values; remove the other", where NAME names the
/// document (a file, or "FILE: metadata 'KEY'") and OBJECT is "the top-level
/// object" or the object's path ("cameras[1]", "grid", "views[0].extras").
nlohmann::json parseJsonInput(std::string_view text, const std::string& name);

/// The same without exceptions for syntax errors: a document that is not
/// valid JSON gives a discarded value (is_discarded()), for readers that leave
/// syntax errors to another parser to report. Duplicate keys still throw.
nlohmann::json parseJsonInputOrDiscarded(std::string_view text, const std::string& name);

}  // namespace vox
