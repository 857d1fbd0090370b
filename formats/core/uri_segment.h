// A file name as one segment of a relative URI reference (RFC 3986), for the
// files a document names beside itself (a .gltf's .bin buffer).
//
// A name is not a URI: in "a#b.bin" a reader takes "#b.bin" for a fragment,
// "a%b.bin" and "a b.bin" are not URI references at all, and a name with a
// ':' before any '/' reads as a scheme. So every byte but the unreserved
// characters (A-Z a-z 0-9 - . _ ~) and ! * ' ( ) (what JavaScript's
// encodeURIComponent keeps) is written as %XX, upper-case hex: '#' as %23,
// '%' as %25, ' ' as %20, and each byte of a UTF-8 name's multi-byte
// characters as its own escape ("é" is %C3%A9). Bytes are encoded as they
// are, so decoding the segment gives back the file's name byte for byte
// (also a name that is not UTF-8). Thread-safety: a pure function.
#pragma once

#include <string>
#include <string_view>

namespace vox {

/// `name` percent-encoded as a URI path segment (see above).
std::string uriPathSegment(std::string_view name);

}  // namespace vox
