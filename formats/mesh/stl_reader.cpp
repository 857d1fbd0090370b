// STL, binary and ASCII. Binary is recognised by its size (84 + 50 n bytes for
// the n its header announces) even when the header starts with "solid", as
// many exporters write.
#include <charconv>
#include <cstring>
#include <filesystem>
#include <string_view>

#include "formats/core/text_numbers.h"
#include "formats/mesh/mesh_input.h"
#include "libvox/core/counted.h"
#include "libvox/core/error.h"
#include "libvox/core/utf8.h"

namespace vox {

namespace {

/// `word` is the STL keyword `lower` in any case: the format's keywords are
/// lower case, but some CAD exporters write them in upper case.
bool keyword(std::string_view word, std::string_view lower) {
  if (word.size() != lower.size()) return false;
  for (size_t i = 0; i < word.size(); ++i)
    if ((word[i] >= 'A' && word[i] <= 'Z' ? char(word[i] - 'A' + 'a') : word[i]) != lower[i]) return false;
  return true;
}

/// Is the file binary STL? It is when its size is the 84 + 50 n bytes its
/// header announces. Otherwise it is ASCII when it is text (no NUL byte) that
/// starts with "solid"; a file that is neither is a binary STL with bytes after
/// its triangles (a warning) or, when shorter than announced, refused.
bool isBinaryStl(const char* data, size_t size, const std::string& name, std::vector<std::string>& warnings) {
  if (size < 84) return false;
  uint32_t n = 0;
  std::memcpy(&n, data + 80, 4);
  const uint64_t binarySize = 84 + 50 * uint64_t(n);
  if (uint64_t(size) == binarySize) return true;
  const char* s = data + utf8BomLength(data, size);
  while (s < data + size && (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')) ++s;
  const bool solid = size_t(data + size - s) >= 5 && keyword(std::string_view(s, 5), "solid");
  if (solid && !std::memchr(data, 0, size)) return false;
  if (uint64_t(size) < binarySize)
    throwBadInput(name + ": " + (solid ? "" : "not ASCII STL (no 'solid'), and as ") + "binary STL it announces " +
                  counted(n, "triangle", "triangles") + " (" + std::to_string(binarySize) + " bytes) but the file has " +
                  std::to_string(size) + " bytes: truncated, or not an STL file");
  warnings.push_back(name + ": binary STL has " + counted(uint64_t(size) - binarySize, "byte", "bytes") +
                     " after its " + counted(n, "triangle", "triangles") + "; ignored");
  return true;
}

/// Binary STL: 80 header bytes, a triangle count, 50 bytes per triangle
/// (normal, three vertices as float32, attribute bytes).
void readBinaryStl(const char* data, Mesh& mesh) {
  uint32_t n = 0;
  std::memcpy(&n, data + 80, 4);
  mesh.positions.reserve(size_t(n) * 3);
  mesh.triangles.reserve(n);
  for (uint32_t t = 0; t < n; ++t) {
    const char* rec = data + 84 + 50 * size_t(t);
    for (int k = 0; k < 3; ++k) {
      float p[3];
      std::memcpy(p, rec + 12 + 12 * k, 12);
      mesh.positions.push_back({p[0], p[1], p[2]});
    }
    mesh.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
}

/// The next word on the line at `p` (empty at the line's end), `p` moved past it.
std::string_view lineWord(const char*& p, const char* end) {
  while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  const char* w = p;
  while (p < end && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
  return {w, size_t(p - w)};
}

/// Past the name after "solid" or "endsolid" (`p` just after the keyword): the
/// rest of the line, which may hold any word ("solid facet model"), unless the
/// line goes on with a facet (an STL written on one line): then up to its
/// "facet normal", or after "endsolid" up to the "solid" that starts it.
const char* pastName(const char* p, const char* end, bool afterEndsolid) {
  const char* solid = nullptr;
  for (;;) {
    const std::string_view w = lineWord(p, end);
    if (w.empty()) return p;
    if (afterEndsolid && keyword(w, "solid")) {
      solid = w.data();
      continue;
    }
    const char* q = p;
    if (keyword(w, "facet") && keyword(lineWord(q, end), "normal")) {
      if (!afterEndsolid) return w.data();
      if (solid) return solid;
    }
  }
}

/// ASCII STL: "solid", then facets ("facet normal ..", "outer loop", three
/// "vertex x y z", "endloop", "endfacet"), then "endsolid"; several solids may
/// follow one another (one per body or colour, as CAD exporters write them),
/// and every one is read. A file that ends inside a facet is refused (a cut-off
/// download or copy); one that ends after a complete facet without "endsolid"
/// is read with a warning; text after an "endsolid" other than another solid
/// is refused, naming its line.
void readAsciiStl(const char* data, size_t size, const std::string& name, Mesh& mesh,
                  std::vector<std::string>& warnings) {
  const char* p = data + utf8BomLength(data, size);
  const char* end = data + size;
  size_t line = 1;
  auto skipSpace = [&] {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) {
      if (*p == '\n') ++line;
      ++p;
    }
  };
  skipSpace();
  if (size_t(end - p) < 5 || !keyword(std::string_view(p, 5), "solid"))
    throwBadInput(name + ": not an STL file (neither a binary STL of consistent size nor ASCII starting with 'solid')");
  p = pastName(p + 5, end, false);
  size_t corners = 0;
  size_t facetLine = 0;   // line of the open "facet", 0 outside one
  size_t endsolidLine = 0;  // line of the last "endsolid", 0 inside a solid
  while (true) {
    skipSpace();
    if (p >= end) break;
    const char* w = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
    const std::string_view word(w, size_t(p - w));
    if (endsolidLine) {
      if (!keyword(word, "solid"))
        throwBadInput(name + ":" + std::to_string(line) + ": '" + std::string(word.substr(0, 40)) +
                      "' after the 'endsolid' of line " + std::to_string(endsolidLine) +
                      "; only another 'solid' may follow one: remove the text or repair the file");
      p = pastName(p, end, false);
      endsolidLine = 0;
    } else if (keyword(word, "facet")) {
      if (facetLine)
        throwBadInput(name + ":" + std::to_string(line) + ": a facet starts before the facet of line " +
                      std::to_string(facetLine) + " ended ('endfacet' missing)");
      facetLine = line;
    } else if (keyword(word, "vertex")) {
      std::array<double, 3> v;
      for (int k = 0; k < 3; ++k) {
        skipSpace();
        auto [ptr, ec] = parseDoubleAllowingPlus(p, end, v[k]);
        if (ec != std::errc()) throwBadInput(name + ":" + std::to_string(line) + ": expected 3 numbers after 'vertex'");
        p = ptr;
      }
      mesh.positions.push_back(v);
      ++corners;
    } else if (keyword(word, "endloop")) {
      if (corners != 3)
        throwBadInput(name + ":" + std::to_string(line) + ": a facet has " +
                      counted(corners, "vertex", "vertices") + "; STL facets are triangles");
      const uint32_t b = uint32_t(mesh.positions.size() - 3);
      mesh.triangles.push_back({b, b + 1, b + 2});
      corners = 0;
    } else if (keyword(word, "endfacet")) {
      facetLine = 0;
    } else if (keyword(word, "endsolid")) {
      if (facetLine || corners)
        throwBadInput(name + ":" + std::to_string(line) + ": 'endsolid' inside the facet of line " +
                      std::to_string(facetLine ? facetLine : line) + " (" + std::to_string(corners) +
                      " of its 3 vertices read); repair or re-export the file");
      endsolidLine = line;
      p = pastName(p, end, true);
    }
  }
  if (facetLine || corners)
    throwBadInput(name + ": the file ends inside the facet of line " +
                  std::to_string(facetLine ? facetLine : line) + " (" + std::to_string(corners) +
                  " of its 3 vertices read): the file is truncated; re-export or copy it again");
  if (!endsolidLine)
    warnings.push_back(name + ": no 'endsolid' after facet " + std::to_string(mesh.triangles.size()) +
                       ": the file may be truncated");
}

}  // namespace

Mesh parseStl(const char* data, size_t size, const std::string& name, const MeshReadOptions& options,
              std::vector<std::string>& warnings) {
  Mesh mesh;
  mesh.materials.push_back({"", {1, 1, 1, 1}, -1, 0});
  mesh.parts.push_back({"", std::filesystem::path(name).filename().string()});
  if (isBinaryStl(data, size, name, warnings)) readBinaryStl(data, mesh);
  else readAsciiStl(data, size, name, mesh, warnings);
  mesh.triangleMaterial.assign(mesh.triangles.size(), 0);
  mesh.trianglePart.assign(mesh.triangles.size(), 0);
  mesh.vertexRuns.push_back({0, name, "vertex", 1, " (counted from 1 over its facets, 3 a facet)"});
  checkFinite(mesh, name, options, warnings);
  return mesh;
}

}  // namespace vox
