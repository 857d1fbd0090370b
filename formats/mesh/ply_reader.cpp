// PLY 1.0: ASCII and binary (little and big endian), any scalar types, vertex
// colours (8-bit sRGB-encoded or float), faces as index lists of any type,
// polygons triangulated (formats/mesh/polygon_triangulation.h); other elements
// are skipped.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "formats/core/text_numbers.h"
#include "formats/mesh/mesh_input.h"
#include "formats/mesh/polygon_triangulation.h"
#include "libvox/core/color.h"
#include "libvox/core/counted.h"
#include "libvox/core/error.h"
#include "libvox/core/utf8.h"

namespace vox {

namespace {
/// A number read from the body, for messages: whole numbers as integers (up
/// to 2^53), anything else as the shortest text that reads back the same.
/// (Casting a double past int64_t's range to it is undefined behaviour.)
std::string numberText(double v) {
  if (v == std::floor(v) && std::fabs(v) < 9007199254740992.0) return std::to_string(int64_t(v));
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::string(text, end);
}

constexpr uint64_t kMaxVertices = uint64_t(1) << 31;

enum class Type { I8, U8, I16, U16, I32, U32, F32, F64 };

bool parseType(const std::string& s, Type& t) {
  static const std::pair<const char*, Type> names[] = {
      {"char", Type::I8},   {"int8", Type::I8},     {"uchar", Type::U8},   {"uint8", Type::U8},
      {"short", Type::I16}, {"int16", Type::I16},   {"ushort", Type::U16}, {"uint16", Type::U16},
      {"int", Type::I32},   {"int32", Type::I32},   {"uint", Type::U32},   {"uint32", Type::U32},
      {"float", Type::F32}, {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};
  for (const auto& [n, v] : names)
    if (s == n) return t = v, true;
  return false;
}

size_t typeSize(Type t) {
  switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    case Type::F64: return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Type type = Type::F32;
  bool list = false;
  Type countType = Type::U8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> props;
};

/// The fewest body bytes one value of `p` can take (ASCII: a digit; binary:
/// its size, or the count's size for a list, which may be empty).
uint64_t minBodyBytes(const Property& p, int format) {
  if (format == 0) return 1;
  return typeSize(p.list ? p.countType : p.type);
}

class Reader {
 public:
  Reader(const char* d, size_t n, std::string name, int format) : p_(d), end_(d + n), name_(std::move(name)), format_(format) {}
  size_t remaining() const { return size_t(end_ - p_); }
  /// The element being read, for messages (built only when something is wrong).
  void at(const std::string* element, uint64_t index) {
    element_ = element;
    index_ = index;
  }
  std::string what() const { return "element '" + *element_ + "' " + std::to_string(index_); }
  // Reads one scalar as double. format: 0 ascii, 1 little, 2 big endian.
  double scalar(Type t) {
    if (format_ == 0) {
      while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n')) ++p_;
      double v = 0;
      auto [ptr, ec] = parseDoubleAllowingPlus(p_, end_, v);
      if (ec != std::errc())
        throwBadInput(name_ + ": " + what() + ": " +
                      (ptr >= end_ ? "the file ends early (truncated?)" : "expected a number in the ASCII body"));
      p_ = ptr;
      return v;
    }
    const size_t n = typeSize(t);
    if (size_t(end_ - p_) < n) throwBadInput(name_ + ": " + what() + ": the file ends early (truncated?)");
    unsigned char b[8];
    std::memcpy(b, p_, n);
    p_ += n;
    if (format_ == 2) std::reverse(b, b + n);
    switch (t) {
      case Type::I8: return double(int8_t(b[0]));
      case Type::U8: return double(b[0]);
      case Type::I16: { int16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::U16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::I32: { int32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::U32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::F32: { float v; std::memcpy(&v, b, 4); return v; }
      case Type::F64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
  }
 private:
  const char* p_;
  const char* end_;
  std::string name_;
  int format_;
  const std::string* element_ = nullptr;
  uint64_t index_ = 0;
};

struct Header {
  int format = -1;  // 0 ascii, 1 binary little endian, 2 binary big endian
  std::vector<Element> elements;
  size_t bodyStart = 0;  // offset of the first body byte (at most the file size)
};

/// The header: format, elements and their properties, where the body starts.
/// It ends at the first line that is "end_header" (a comment may contain those
/// words too).
Header parseHeader(const char* data, size_t size, const std::string& name) {
  const std::string_view all(data, size);
  size_t headerEnd = std::string_view::npos;
  for (size_t ls = 0; ls < size;) {
    size_t le = all.find('\n', ls);
    if (le == std::string_view::npos) le = size;
    std::string_view l = all.substr(ls, le - ls);
    while (!l.empty() && (l.back() == '\r' || l.back() == ' ' || l.back() == '\t')) l.remove_suffix(1);
    if (l == "end_header") {
      headerEnd = ls;
      break;
    }
    ls = le + 1;
  }
  if (size < 3 || std::strncmp(data, "ply", 3) != 0 || headerEnd == std::string_view::npos)
    throwBadInput(name + ": not a PLY file (no 'ply' magic or no 'end_header' line)");
  std::istringstream text(std::string(data, headerEnd));
  std::string line;
  Header h;
  size_t lineNo = 0;
  while (std::getline(text, line)) {
    ++lineNo;
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "format") {
      std::string f, version;
      ls >> f >> version;
      h.format = f == "ascii" ? 0 : f == "binary_little_endian" ? 1 : f == "binary_big_endian" ? 2 : -1;
      if (h.format < 0) throwBadInput(name + ":" + std::to_string(lineNo) + ": unknown PLY format '" + f + "'");
      // 1.0 is the only version there is (written "1.0", or "1" by a few
      // tools); another could lay its body out otherwise.
      double number = 0;
      const auto [end, ec] = std::from_chars(version.data(), version.data() + version.size(), number);
      if (version.empty() || ec != std::errc() || end != version.data() + version.size() || number != 1)
        throwBadInput(name + ":" + std::to_string(lineNo) + ": " +
                      (version.empty() ? std::string("the format line gives no version")
                                       : "PLY version '" + version + "' is not one vox reads") +
                      " (only 1.0: 'format " + f + " 1.0'); write the file as PLY 1.0");
    } else if (key == "element") {
      Element e;
      ls >> e.name >> e.count;
      if (!ls) throwBadInput(name + ":" + std::to_string(lineNo) + ": malformed element line");
      h.elements.push_back(e);
    } else if (key == "property") {
      if (h.elements.empty()) throwBadInput(name + ":" + std::to_string(lineNo) + ": property before any element");
      Property p;
      std::string t;
      ls >> t;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it >> p.name;
        if (!parseType(ct, p.countType) || !parseType(it, p.type))
          throwBadInput(name + ":" + std::to_string(lineNo) + ": unknown list types '" + ct + " " + it + "'");
        p.list = true;
      } else {
        ls >> p.name;
        if (!parseType(t, p.type)) throwBadInput(name + ":" + std::to_string(lineNo) + ": unknown property type '" + t + "'");
      }
      h.elements.back().props.push_back(p);
    }
  }
  if (h.format < 0) throwBadInput(name + ": the PLY header has no 'format' line");
  size_t bodyStart = headerEnd + 10;
  while (bodyStart < size && data[bodyStart] != '\n') ++bodyStart;
  h.bodyStart = std::min(bodyStart + 1, size);
  return h;
}

/// Which properties of an element vertices and faces are made of (-1: absent).
struct Roles {
  int x = -1, y = -1, z = -1, red = -1, green = -1, blue = -1, alpha = -1, faceIndices = -1;
  explicit Roles(const Element& e) {
    for (size_t k = 0; k < e.props.size(); ++k) {
      const std::string& n = e.props[k].name;
      if (n == "x") x = int(k);
      if (n == "y") y = int(k);
      if (n == "z") z = int(k);
      if (n == "red" || n == "r") red = int(k);
      if (n == "green" || n == "g") green = int(k);
      if (n == "blue" || n == "b") blue = int(k);
      if (n == "alpha" || n == "a") alpha = int(k);
      if ((n == "vertex_indices" || n == "vertex_index") && e.props[k].list) faceIndices = int(k);
    }
  }
};

/// The triangles of one triangle strip of "tristrips" (older Stanford and
/// VCG/MeshLab files): index -1 restarts the strip, every other triangle is
/// flipped to keep the strip's winding, and the degenerate triangles that
/// join strips (a repeated index) are left out.
void addStripTriangles(const std::vector<int64_t>& strip, Mesh& mesh) {
  size_t start = 0;
  for (size_t j = 0; j < strip.size(); ++j) {
    if (strip[j] < 0) {
      start = j + 1;
      continue;
    }
    if (j < start + 2) continue;
    const uint32_t a = uint32_t(strip[j - 2]), b = uint32_t(strip[j - 1]), c = uint32_t(strip[j]);
    if (a == b || b == c || a == c) continue;
    if ((j - start) % 2 == 0) mesh.triangles.push_back({a, b, c});
    else mesh.triangles.push_back({b, a, c});
  }
}

/// Faces of fewer than 3 corners, dropped under MeshReadOptions::dropInvalid.
struct DroppedFaces {
  uint64_t count = 0, first = 0;
};

/// Reads every item of element `e` from the body: a "vertex" adds a position
/// (and colour), a "face" adds its polygon's triangles, a "tristrips" its
/// strips' triangles, any other element is read past.
void readElement(Reader& r, const Element& e, int format, const std::string& name, Mesh& mesh,
                 const MeshReadOptions& options, DroppedFaces& dropped) {
  const bool isVertex = e.name == "vertex", isStrips = e.name == "tristrips", isFace = e.name == "face" || isStrips;
  const Roles role(e);
  if (isVertex && (role.x < 0 || role.y < 0 || role.z < 0)) throwBadInput(name + ": element 'vertex' lacks x, y or z");
  if (e.props.empty()) return;  // an element without properties has no bytes in the body
  // Every item takes at least one byte per scalar property (and per list
  // count): refuse counts the rest of the file cannot hold before looping.
  uint64_t minBytes = 0;
  for (const Property& p : e.props) minBytes += minBodyBytes(p, format);
  if (minBytes && e.count > r.remaining() / minBytes)
    throwBadInput(name + ": element '" + e.name + "' announces " + counted(e.count, "item", "items") + " but only " +
                  counted(r.remaining(), "byte follows", "bytes follow") +
                  " the header (truncated, or a wrong count?)");
  // Mesh indices are 32-bit; a file that big is checked after the one above,
  // so that a count the file cannot hold gets the same message at any size.
  if (isVertex && e.count > kMaxVertices)
    throwBadInput(name + ": element 'vertex' announces " + std::to_string(e.count) + " vertices; vox reads at most " +
                  std::to_string(kMaxVertices) + " (2^31) from one file: split the mesh into several files");
  const bool hasColor = role.red >= 0 && role.green >= 0 && role.blue >= 0;
  std::vector<double> vals(e.props.size());
  std::vector<uint32_t> poly;
  std::vector<int64_t> strip;
  std::vector<std::array<double, 3>> corners;
  std::vector<std::array<uint32_t, 3>> triangles;
  PolygonScratch scratch;
  for (uint64_t i = 0; i < e.count; ++i) {
    r.at(&e.name, i);
    for (size_t k = 0; k < e.props.size(); ++k) {
      const Property& p = e.props[k];
      if (!p.list) {
        vals[k] = r.scalar(p.type);
        continue;
      }
      const double count = r.scalar(p.countType);
      if (!(count >= 0 && count <= 1e6) || count != std::floor(count))
        throwBadInput(name + ": " + r.what() + ": list of " + numberText(count) + (count == 1 ? " entry" : " entries"));
      const bool faceIndices = isFace && int(k) == role.faceIndices;
      poly.clear();
      strip.clear();
      for (int j = 0; j < int(count); ++j) {
        const double v = r.scalar(p.type);
        if (!faceIndices) continue;
        if (isStrips && v == -1) {  // a strip restarts
          strip.push_back(-1);
          continue;
        }
        // NaN and fractions too: a float-typed index list reads as numbers
        // that need not be whole (uint32_t(NaN) is undefined).
        if (v != std::floor(v))
          throwBadInput(name + ": " + (isStrips ? "tristrips " : "face ") + std::to_string(i) + " has vertex index " +
                        numberText(v) + ", which is not a whole number");
        if (v < 0 || v >= double(mesh.positions.size()))
          throwBadInput(name + ": " + (isStrips ? "tristrips " : "face ") + std::to_string(i) + " refers to vertex " +
                        numberText(v) + " but there are " + std::to_string(mesh.positions.size()));
        if (isStrips) strip.push_back(int64_t(v));
        else poly.push_back(uint32_t(v));
      }
      if (faceIndices && isStrips) {
        addStripTriangles(strip, mesh);
      } else if (faceIndices && poly.size() < 3) {
        if (!options.dropInvalid)
          throwBadInput(name + ": face " + std::to_string(i) + " has " + counted(poly.size(), "vertex", "vertices") +
                            "; a face needs at least 3: fix the file or drop such faces",
                        Setting::DropInvalid);
        if (!dropped.count++) dropped.first = i;
      } else if (faceIndices) {
        corners.clear();
        for (const uint32_t v : poly) corners.push_back(mesh.positions[v]);
        triangles.clear();
        triangulatePolygon(corners.data(), corners.size(), triangles, scratch);
        for (const auto& t : triangles) mesh.triangles.push_back({poly[t[0]], poly[t[1]], poly[t[2]]});
      }
    }
    if (isVertex) {
      mesh.positions.push_back({vals[size_t(role.x)], vals[size_t(role.y)], vals[size_t(role.z)]});
      if (hasColor) {
        const Type type = e.props[size_t(role.red)].type;
        const bool floats = type == Type::F32 || type == Type::F64;
        auto lin = [&](double c) { return floats ? float(c) : srgbToLinear(c / 255.0); };
        mesh.colors.push_back({lin(vals[size_t(role.red)]), lin(vals[size_t(role.green)]), lin(vals[size_t(role.blue)]),
                               role.alpha >= 0 ? float(floats ? vals[size_t(role.alpha)] : vals[size_t(role.alpha)] / 255.0)
                                               : 1.0f});
      }
    }
  }
}

}  // namespace

Mesh parsePly(const char* data, size_t size, const std::string& name, const MeshReadOptions& options,
              std::vector<std::string>& warnings) {
  const size_t bom = utf8BomLength(data, size);
  data += bom, size -= bom;
  const Header header = parseHeader(data, size, name);
  Reader r(data + header.bodyStart, size - header.bodyStart, name, header.format);
  Mesh mesh;
  mesh.materials.push_back({"", {1, 1, 1, 1}, -1, 0});
  mesh.parts.push_back({"", std::filesystem::path(name).filename().string()});
  DroppedFaces dropped;
  for (const Element& e : header.elements) readElement(r, e, header.format, name, mesh, options, dropped);
  if (dropped.count)
    warnings.push_back(name + ": dropped " + counted(dropped.count, "face", "faces") +
                       " of fewer than 3 vertices (the first is face " + std::to_string(dropped.first) + ")");
  mesh.triangleMaterial.assign(mesh.triangles.size(), 0);
  mesh.trianglePart.assign(mesh.triangles.size(), 0);
  mesh.vertexRuns.push_back({0, name, "vertex", 0, " (counted from 0, as its faces count them)"});
  checkFinite(mesh, name, options, warnings);
  return mesh;
}

}  // namespace vox
