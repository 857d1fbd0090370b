// Wavefront OBJ + MTL. Hand-written rather than a library: numbers read as
// std::from_chars reads them but faster (formats/core/text_numbers.h), no
// per-line allocation, which is what reaching 100 MB/s takes. A large file
// is read in two passes: its "v" and "f" lines' numbers in parallel, chunk by
// chunk (the numbers are most of the work), then every line in file order on
// one thread (index resolution, vertex numbering, materials, errors), so the
// mesh and every message are those of a single pass.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <unordered_map>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "formats/core/file_util.h"
#include "formats/core/text_numbers.h"
#include "libvox/core/color.h"
#include "libvox/core/counted.h"
#include "formats/mesh/mesh_input.h"
#include "formats/mesh/polygon_triangulation.h"
#include "formats/mesh/texture_image.h"
#include "libvox/core/error.h"
#include "libvox/core/ordered_pipeline.h"
#include "libvox/core/parallel.h"
#include "libvox/core/utf8.h"

namespace vox {

namespace {

struct Cursor {
  const char* p;
  const char* end;
  size_t line = 1;
  bool atEol() const { return p >= end || *p == '\n' || *p == '\r'; }
  void skipSpaces() {
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
  }
  void nextLine() {
    while (p < end && *p != '\n') ++p;
    if (p < end) ++p;
    ++line;
  }
  std::string_view word() {
    skipSpaces();
    const char* b = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != '\n' && *p != '\r') ++p;
    return {b, size_t(p - b)};
  }
  std::string rest() {  // the rest of the line, trimmed
    skipSpaces();
    const char* b = p;
    while (p < end && *p != '\n') ++p;
    const char* e = p;
    while (e > b && (e[-1] == '\r' || e[-1] == ' ' || e[-1] == '\t')) --e;
    return std::string(b, e);
  }
};

/// Classic Mac OS ended lines with a CR alone: a CR not followed by an LF ends
/// a line, as text editors read it (otherwise the whole file, or the rest of a
/// line after such a CR, would be one line and read as nothing). Returns false
/// when `data` has none; else `lf` is the text with each such CR an LF.
bool loneCrAsLf(const char* data, size_t size, std::string& lf) {
  const char* end = data + size;
  const char* p = data;
  for (; (p = static_cast<const char*>(std::memchr(p, '\r', size_t(end - p)))) != nullptr; ++p)
    if (p + 1 == end || p[1] != '\n') break;
  if (!p) return false;
  lf.assign(data, size);
  for (size_t i = size_t(p - data); i < size; ++i)
    if (lf[i] == '\r' && (i + 1 == size || lf[i + 1] != '\n')) lf[i] = '\n';
  return true;
}

/// The lines that start "v " and "f ", which the reader's arrays are reserved
/// for. 16 bytes a step (a '\n', the letter after it, a space after that):
/// a memchr per line took 1.7 ms of the Stanford bunny's 10 ms read.
void countVertexAndFaceLines(const char* data, size_t size, size_t& vLines, size_t& fLines) {
  vLines = fLines = 0;
  auto lineAt = [&](size_t p) {  // p starts a line
    if (p + 1 < size && data[p + 1] == ' ') vLines += data[p] == 'v', fLines += data[p] == 'f';
  };
  if (size > 0) lineAt(0);
  size_t i = 0;  // the next byte that may be the '\n' before a line
#ifdef __SSE2__
  const __m128i newline = _mm_set1_epi8('\n'), space = _mm_set1_epi8(' '), v = _mm_set1_epi8('v'),
                f = _mm_set1_epi8('f');
  for (; i + 18 <= size; i += 16) {
    const auto at = [&](size_t k) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(data + i + k)); };
    const unsigned starts = unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(at(0), newline))) &
                            unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(at(2), space)));
    if (!starts) continue;
    const __m128i letter = at(1);
    vLines += size_t(std::popcount(starts & unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(letter, v)))));
    fLines += size_t(std::popcount(starts & unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(letter, f)))));
  }
#endif
  for (; i < size; ++i)
    if (data[i] == '\n') lineAt(i + 1);
}

[[noreturn]] void bad(const std::string& name, size_t line, const std::string& what, Setting fix = Setting::None) {
  throwBadInput(name + ":" + std::to_string(line) + ": " + what, fix);
}

double number(Cursor& c, const std::string& name, const char* what) {
  c.skipSpaces();
  double v = 0;
  auto [ptr, ec] = parseDoubleAllowingPlus(c.p, c.end, v);
  if (ec != std::errc()) bad(name, c.line, std::string("expected a number for ") + what);
  c.p = ptr;
  return v;
}

/// True when `path` names a regular file; never throws (a name too long or
/// otherwise invalid is simply not a file).
bool isFile(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

MeshTexture loadTexture(const std::string& path, const std::string& mtlName, size_t line,
                        std::vector<std::string>& warnings) {
  if (!isFile(path))
    throwBadInput(mtlName + ":" + std::to_string(line) + ": map_Kd " + path +
                      ": the texture file is missing; restore it, remove the map_Kd line, or leave the texture out",
                  Setting::IgnoreMissingMaterials);
  const std::string bytes = readFileBytes(path);
  TextureImage image;
  std::string why;
  if (!decodeTextureImage(bytes, image, why))
    throwBadInput(mtlName + ":" + std::to_string(line) + ": map_Kd " + path + ": cannot decode the image (" + why + ")");
  if (!image.warning.empty())
    warnings.push_back(damagedImageWarning(mtlName + ":" + std::to_string(line) + ": map_Kd " + path, image.warning));
  MeshTexture t;
  t.width = image.width;
  t.height = image.height;
  t.rgba = std::move(image.rgba);
  t.source = path;
  return t;
}

/// `file` (as written in an OBJ/MTL) relative to `dir`. Files written on
/// Windows use '\\' as separator (".\\tex.jpg"): when the name as written does
/// not exist, try it with '/'.
std::string resolvePath(const std::string& dir, const std::string& file) {
  std::string full = (std::filesystem::path(dir) / file).string();
  if (file.find('\\') != std::string::npos && !isFile(full)) {
    std::string slashed = file;
    for (char& ch : slashed)
      if (ch == '\\') ch = '/';
    const std::string alt = (std::filesystem::path(dir) / slashed).lexically_normal().string();
    if (isFile(alt)) return alt;
  }
  return full;
}

/// A map_Kd statement's rest: its options (the MTL format's "-name args..."),
/// then the file name, which may hold spaces ("map_Kd -bm 1 my texture.png").
struct TextureStatement {
  std::string file;
  std::array<double, 2> offset{0, 0}, scale{1, 1};  // -o u v, -s u v (the w of 3D textures is not used)
  std::string turbulence;  // a -t other than 0 0 0, as written: not applied (it is random)
  bool clamp = false;      // "-clamp on": texture coordinates clamped to [0, 1] instead of repeated
};

/// The placement -o and -s give, as a MeshMaterial::uvTransform. The MTL
/// format scales and then offsets its (u, v) (v = 0 at the bottom), as the
/// importers of Blender (a Mapping node) and three.js (repeat, offset) read
/// it: u' = su u + ou, v' = sv v + ov; in the mesh's (s, t = 1 - v):
/// s' = su s + ou, t' = sv t + 1 - sv - ov.
std::array<double, 6> placementOf(const TextureStatement& st) {
  return {st.scale[0], 0, st.offset[0], 0, st.scale[1], 1 - st.scale[1] - st.offset[1]};
}

TextureStatement textureStatement(const std::string& rest) {
  // Each option and how many words follow it; -3: -o, -s and -t take 1 to 3 numbers.
  static const std::unordered_map<std::string, int> kArgs = {
      {"-blendu", 1}, {"-blendv", 1}, {"-bm", 1},      {"-boost", 1}, {"-cc", 1}, {"-clamp", 1},
      {"-imfchan", 1}, {"-mm", 2},    {"-texres", 1}, {"-type", 1},  {"-o", -3}, {"-s", -3}, {"-t", -3}};
  TextureStatement st;
  size_t pos = 0;
  auto nextWord = [&](size_t& at) {
    while (at < rest.size() && (rest[at] == ' ' || rest[at] == '\t')) ++at;
    const size_t b = at;
    while (at < rest.size() && rest[at] != ' ' && rest[at] != '\t') ++at;
    return rest.substr(b, at - b);
  };
  for (;;) {
    size_t at = pos;
    const std::string option = nextWord(at);
    const auto known = kArgs.find(option);
    if (known == kArgs.end()) break;  // the file name starts here
    pos = at;
    if (known->second > 0) {
      for (int k = 0; k < known->second; ++k) {
        const std::string arg = nextWord(pos);
        if (option == "-clamp") st.clamp = arg == "on";
      }
      continue;
    }
    // -o, -s, -t: up to three numbers, u then the optional v and w (0 by
    // default for -o and -t, 1 for -s).
    const double neutral = option == "-s" ? 1.0 : 0.0;
    std::string written = option;
    bool moves = false;
    for (int k = 0; k < 3; ++k) {
      size_t after = pos;
      const std::string w = nextWord(after);
      double v = 0;
      const auto [ptr, ec] = parseDoubleAllowingPlus(w.data(), w.data() + w.size(), v);
      if (w.empty() || ec != std::errc() || ptr != w.data() + w.size()) break;
      pos = after;
      written += " " + w;
      moves |= v != neutral;
      if (k < 2 && option == "-o") st.offset[size_t(k)] = v;
      if (k < 2 && option == "-s") st.scale[size_t(k)] = v;
    }
    if (moves && option == "-t") st.turbulence = written;
  }
  while (pos < rest.size() && (rest[pos] == ' ' || rest[pos] == '\t')) ++pos;
  st.file = rest.substr(pos);
  return st;
}

/// Parses an MTL file into `mesh.materials` (names -> index in `byName`).
/// `undefined`: materials a "usemtl" named before any library defined them
/// (index -> the line naming it); a library read later that defines one fills
/// it in, so the faces before the "mtllib" take its colour as well.
void parseMtl(const std::string& path, Mesh& mesh, std::unordered_map<std::string, uint32_t>& byName,
              std::unordered_map<uint32_t, size_t>& undefined, const MeshReadOptions& options,
              std::vector<std::string>& warnings) {
  std::string text = readFileBytes(path);
  if (std::string lf; loneCrAsLf(text.data(), text.size(), lf)) text = std::move(lf);
  mesh.filesRead.push_back(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  Cursor c{text.data() + utf8BomLength(text.data(), text.size()), text.data() + text.size()};
  int current = -1;
  while (c.p < c.end) {
    const std::string_view key = c.word();
    if (key == "newmtl") {
      MeshMaterial m;
      m.name = c.rest();
      const auto named = byName.find(m.name);
      if (named != byName.end() && undefined.erase(named->second)) {  // named by a "usemtl" before this library
        current = int(named->second);
        mesh.materials[size_t(current)] = m;
      } else {
        current = int(mesh.materials.size());
        byName[m.name] = uint32_t(current);
        mesh.materials.push_back(m);
      }
    } else if (key == "Kd" && current >= 0) {
      // OBJ/MTL colours are conventionally linear reflectances.
      for (int k = 0; k < 3; ++k) mesh.materials[current].baseColorFactor[k] = float(number(c, path, "Kd"));
    } else if (key == "map_Kd" && current >= 0) {
      const TextureStatement st = textureStatement(c.rest());
      std::string file = st.file;
      // Files written before options were parsed were read by their last word:
      // keep reading "map_Kd unknown-option tex.png" so.
      std::string full = resolvePath(dir, file);
      if (const size_t sp = file.find_last_of(" \t"); sp != std::string::npos && !isFile(full)) {
        const std::string last = file.substr(sp + 1);
        if (isFile(resolvePath(dir, last))) file = last, full = resolvePath(dir, last);
      }
      if (!st.turbulence.empty())
        warnings.push_back(path + ":" + std::to_string(c.line) + ": map_Kd " + file + ": " + st.turbulence +
                           " (turbulence) is not applied: material '" + mesh.materials[current].name +
                           "' takes its texels without the random displacement");
      mesh.materials[current].uvTransform = placementOf(st);
      if (options.ignoreMissingMaterials && !isFile(full)) {
        warnings.push_back(path + ":" + std::to_string(c.line) + ": map_Kd " + file +
                           ": the texture file is missing; material '" + mesh.materials[current].name +
                           "' is left untextured");
        c.nextLine();
        continue;
      }
      mesh.textures.push_back(loadTexture(full, path, c.line, warnings));
      if (st.clamp) mesh.textures.back().wrapS = mesh.textures.back().wrapT = MeshTexture::Wrap::ClampToEdge;
      mesh.filesRead.push_back(full);
      mesh.materials[current].texture = int(mesh.textures.size() - 1);
    }
    c.nextLine();
  }
}

/// One OBJ file being parsed: the state its lines build up, one method per
/// kind of line. Positions, texture coordinates and colours are kept as the
/// file numbers them ("obj" indices) until a face uses them: mesh vertices
/// are made per (v, vt) pair a face refers to.
class ObjParser {
 public:
  ObjParser(const std::string& name, const MeshReadOptions& options, std::vector<std::string>& warnings,
            const std::string& baseDir)
      : name_(name), options_(options), warnings_(warnings), baseDir_(baseDir) {
    mesh_.parts.push_back({"", std::filesystem::path(name).filename().string()});
  }

  /// Reserves the arrays from a count of "v " and "f " lines (memchr runs at
  /// GB/s): growing them by doubling copied and faulted in twice their final
  /// size, which cost more than parsing the numbers.
  void reserveFor(const char* data, size_t size) {
    size_t vLines = 0, fLines = 0;
    countVertexAndFaceLines(data, size, vLines, fLines);
    objPositions_.reserve(vLines);
    vertexOfObj_.reserve(vLines);
    objOfVertex_.reserve(vLines);
    mesh_.positions.reserve(vLines);
    mesh_.triangles.reserve(fLines);
    mesh_.triangleMaterial.reserve(fLines);
    mesh_.trianglePart.reserve(fLines);
  }

  /// "v x y z [w]" or "v x y z r g b [a]" (MeshLab, ZBrush and most scanners:
  /// colours in [0, 1] written from 8-bit sRGB, so decoded to linear like PLY bytes).
  void vertex(Cursor& c) {
    std::array<double, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = number(c, name_, "a vertex coordinate");
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      if (!invalidVertices_++) firstInvalidLine_ = c.line, firstInvalidVertex_ = objPositions_.size() + 1;
    }
    objPositions_.push_back(p);
    vertexOfObj_.push_back(UINT32_MAX);
    // Optional trailing numbers: w (1 value, ignored), r g b (3) or r g b a (4).
    double extra[4];
    int n = 0;
    for (c.skipSpaces(); !c.atEol() && *c.p != '#'; c.skipSpaces()) {
      if (n == 4) bad(name_, c.line, "a vertex has more than 7 numbers; expected x y z [w] or x y z r g b [a]");
      extra[n++] = number(c, name_, "a vertex colour");
    }
    std::array<float, 4> color{1, 1, 1, 1};
    if (n == 2) bad(name_, c.line, "a vertex has 5 numbers; expected x y z [w] or x y z r g b [a]");
    if (n >= 3) {
      for (int k = 0; k < n; ++k)
        if (!(extra[k] >= 0 && extra[k] <= 1))
          bad(name_, c.line, "vertex colour component " + std::to_string(extra[k]) +
                                 " is outside [0, 1]; OBJ vertex colours are read as fractions of 1, as MeshLab writes"
                                 " them (a file with 0-255 colours needs them divided by 255)");
      for (int k = 0; k < 3; ++k) color[size_t(k)] = srgbToLinear(extra[k]);
      if (n == 4) color[3] = float(extra[3]);
      if (!anyVertexColor_) objColors_.assign(objPositions_.size() - 1, {1, 1, 1, 1});  // the white ones before
      anyVertexColor_ = true;
    }
    if (anyVertexColor_) objColors_.push_back(color);
  }

  /// A "v x y z" line the pre-pass read (no w, no colour): what vertex() does with it.
  void parsedVertex(const std::array<double, 3>& p, size_t line) {
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      if (!invalidVertices_++) firstInvalidLine_ = line, firstInvalidVertex_ = objPositions_.size() + 1;
    }
    objPositions_.push_back(p);
    vertexOfObj_.push_back(UINT32_MAX);
    if (anyVertexColor_) objColors_.push_back({1, 1, 1, 1});
  }

  /// An "f" line of `n` plain vertex indices (as written) that the pre-pass
  /// read: what face() does with it.
  void parsedFace(const int32_t* v, size_t n, size_t line) {
    face_.clear();
    for (size_t k = 0; k < n; ++k) face_.push_back({resolve(v[k], objPositions_.size(), line, "vertex"), -1});
    triangulate(line);
  }

  /// "vt s [t]".
  void texcoord(Cursor& c) {
    const float s = float(number(c, name_, "a texture coordinate"));
    c.skipSpaces();
    const float t = c.atEol() ? 0.0f : float(number(c, name_, "a texture coordinate"));
    if (!std::isfinite(s) || !std::isfinite(t))
      bad(name_, c.line, "a texture coordinate is not a finite number (NaN, or beyond a float's range); "
                         "fix or remove this vt line");
    texcoords_.push_back({s, t});
  }

  /// "f v[/vt[/vn]] ..." (at least 3 corners, negative indices count back),
  /// triangulated, in the current material and part.
  void face(Cursor& c) {
    readCorners(c);
    triangulate(c.line);
  }

  /// face_ as triangles of the current material and part: a polygon as
  /// formats/mesh/polygon_triangulation.h cuts it (convex ones fan-wise).
  void triangulate(size_t line) {
    if (face_.size() < 3) {  // refused, or dropped and counted as faces with non-finite vertices are
      if (!options_.dropInvalid)
        bad(name_, line, "a face has " + counted(face_.size(), "vertex", "vertices") +
                             "; a face needs at least 3: fix the line or drop such faces",
            Setting::DropInvalid);
      if (!shortFaces_++) firstShortFaceLine_ = line;
      return;
    }
    if (currentMaterial_ < 0) currentMaterial_ = defaultMaterial();
    // Mesh vertices are made in corner order, as the fan always made them.
    cornerVertex_.clear();
    for (const Corner& c : face_) cornerVertex_.push_back(meshVertex(c));
    if (face_.size() == 3) return addTriangle({cornerVertex_[0], cornerVertex_[1], cornerVertex_[2]});
    cornerAt_.clear();
    for (const Corner& c : face_) cornerAt_.push_back(objPositions_[c.v]);
    polygon_.clear();
    triangulatePolygon(cornerAt_.data(), cornerAt_.size(), polygon_, polygonScratch_);
    for (const auto& t : polygon_) addTriangle({cornerVertex_[t[0]], cornerVertex_[t[1]], cornerVertex_[t[2]]});
  }

  void addTriangle(const std::array<uint32_t, 3>& t) {
    mesh_.triangles.push_back(t);
    mesh_.triangleMaterial.push_back(uint32_t(currentMaterial_));
    mesh_.trianglePart.push_back(currentPart_);
  }

  /// "o NAME" or "g NAME": the faces that follow form a part of that name.
  void part(Cursor& c) {
    const std::string n = c.rest();
    mesh_.parts.push_back({n, std::filesystem::path(name_).filename().string()});
    currentPart_ = uint32_t(mesh_.parts.size() - 1);
  }

  /// "usemtl NAME". A material no MTL defines keeps its name (class rules
  /// match it) and is white.
  void useMaterial(Cursor& c) {
    const std::string n = c.rest();
    auto it = materialByName_.find(n);
    if (it == materialByName_.end()) {
      mesh_.materials.push_back({n, {1, 1, 1, 1}, -1, 0});
      it = materialByName_.emplace(n, uint32_t(mesh_.materials.size() - 1)).first;
      undefinedMaterials_.emplace(it->second, c.line);  // a library later in the file may still define it
    }
    currentMaterial_ = it->second;
  }

  /// "mtllib a.mtl b.mtl" names several files; a single name may contain spaces.
  void materialLibraries(Cursor& c) {
    const std::string all = c.rest();
    std::vector<std::string> files{all};
    if (!isFile(resolvePath(baseDir_, all))) {
      files.clear();
      for (size_t b = 0; b < all.size();) {
        const size_t e = std::min(all.find_first_of(" \t", b), all.size());
        if (e > b) files.push_back(all.substr(b, e - b));
        b = e + 1;
      }
    }
    for (const std::string& file : files) {
      const std::string full = resolvePath(baseDir_, file);
      if (options_.ignoreMissingMaterials && !isFile(full)) {
        warnings_.push_back(name_ + ":" + std::to_string(c.line) + ": mtllib " + file +
                            ": the material library is missing; its materials are white");
        continue;
      }
      std::error_code ec;
      if (!std::filesystem::exists(full, ec))  // not a regular file: parseMtl names what it is
        throwBadInput(name_ + ":" + std::to_string(c.line) + ": mtllib " + file + ": the material library " + full +
                          " is missing; restore it, or bake without it (its materials white)",
                      Setting::IgnoreMissingMaterials);
      try {
        parseMtl(full, mesh_, materialByName_, undefinedMaterials_, options_, warnings_);
      } catch (const Error& e) {
        throwBadInput(name_ + ":" + std::to_string(c.line) + ": mtllib " + file + ": " + e.what(), e.setting);
      }
    }
  }

  /// The mesh, once every line is read: per-vertex arrays completed, and
  /// non-finite vertices refused (naming the first bad "v" line) or dropped.
  Mesh finish() {
    std::vector<std::pair<size_t, uint32_t>> undefined;  // (line, material), in file order
    for (const auto& [material, line] : undefinedMaterials_) undefined.emplace_back(line, material);
    std::sort(undefined.begin(), undefined.end());
    for (const auto& [line, material] : undefined)
      warnings_.push_back(name_ + ":" + std::to_string(line) + ": material '" + mesh_.materials[material].name +
                          "' is not defined in any mtllib");
    if (shortFaces_)
      warnings_.push_back(name_ + ":" + std::to_string(firstShortFaceLine_) + ": dropped " +
                          counted(shortFaces_, "face", "faces") + " of fewer than 3 vertices (the first on this line)");
    if (mesh_.materials.empty()) mesh_.materials.push_back({"", {1, 1, 1, 1}, -1, 0});
    if (!mesh_.uv0.empty()) mesh_.uv0.resize(mesh_.positions.size(), {0, 0});
    if (anyVertexColor_) {  // vertices written without a colour are white
      mesh_.colors.resize(mesh_.positions.size());
      for (size_t i = 0; i < mesh_.positions.size(); ++i) mesh_.colors[i] = objColors_[objOfVertex_[i]];
    }
    // Name the first bad "v" line (the generic check below only knows mesh vertex numbers).
    if (invalidVertices_ && !options_.dropInvalid)
      bad(name_, firstInvalidLine_,
          counted(invalidVertices_, "vertex has", "vertices have") + " NaN or infinite coordinates (the first is vertex " +
              std::to_string(firstInvalidVertex_) + ", on this line); fix the file or drop their triangles",
          Setting::DropInvalid);
    // Messages name a vertex by its "v" number, as "f" lines do (a "v" used
    // with several "vt" is several mesh vertices): 4 bytes a vertex, kept.
    mesh_.vertexRuns.push_back({0, name_, "vertex", 1, " (as its 'f' lines number them)"});
    mesh_.fileVertex = std::move(objOfVertex_);
    for (uint32_t& v : mesh_.fileVertex) ++v;
    checkFinite(mesh_, name_, options_, warnings_);
    return std::move(mesh_);
  }

 private:
  struct Corner {
    uint32_t v;  // obj position index
    int64_t vt;  // obj texcoord index, -1: none
  };

  /// Index `idx` as written (1-based, or negative counting back from the
  /// `count` defined so far) as a 0-based index.
  uint32_t resolve(int64_t idx, size_t count, size_t line, const char* what) const {
    const int64_t i = idx < 0 ? int64_t(count) + idx : idx - 1;
    if (idx == 0 || i < 0 || i >= int64_t(count))
      bad(name_, line, std::string("face refers to ") + what + " " + std::to_string(idx) + " but " +
                           std::to_string(count) + " are defined so far");
    return uint32_t(i);
  }

  /// The corners of an "f" line into face_.
  void readCorners(Cursor& c) {
    face_.clear();
    while (true) {
      c.skipSpaces();
      if (c.atEol() || *c.p == '#') break;  // a comment may end the line
      int64_t v = 0, vt = 0;
      auto [ptr, ec] = parseInt64(c.p, c.end, v);
      if (ec != std::errc()) bad(name_, c.line, "expected a vertex index in the face");
      c.p = ptr;
      int64_t vtIndex = -1;
      if (c.p < c.end && *c.p == '/') {
        ++c.p;
        if (c.p < c.end && *c.p != '/') {
          auto [p2, e2] = parseInt64(c.p, c.end, vt);
          if (e2 != std::errc()) bad(name_, c.line, "expected a texture coordinate index after '/'");
          c.p = p2;
          vtIndex = resolve(vt, texcoords_.size(), c.line, "texture coordinate");
        }
        if (c.p < c.end && *c.p == '/') {  // normal index: read and ignore
          ++c.p;
          int64_t vn = 0;
          auto [p3, e3] = parseInt64(c.p, c.end, vn);
          if (e3 == std::errc()) c.p = p3;
        }
      }
      face_.push_back({resolve(v, objPositions_.size(), c.line, "vertex"), vtIndex});
      if (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\n' && *c.p != '\r' && *c.p != '#')
        bad(name_, c.line, "unexpected character in a face");
    }
  }

  /// The unnamed white material of faces before any "usemtl", made once.
  int64_t defaultMaterial() {
    if (defaultMaterial_ < 0) {
      defaultMaterial_ = int64_t(mesh_.materials.size());
      mesh_.materials.push_back({"", {1, 1, 1, 1}, -1, 0});
    }
    return defaultMaterial_;
  }

  /// The mesh vertex of a corner: one per obj position without a texture
  /// coordinate, one per (v, vt) pair with one.
  uint32_t meshVertex(const Corner& c) {
    if (c.vt < 0) {
      if (vertexOfObj_[c.v] == UINT32_MAX) {
        vertexOfObj_[c.v] = uint32_t(mesh_.positions.size());
        mesh_.positions.push_back(objPositions_[c.v]);
        objOfVertex_.push_back(c.v);
        if (!mesh_.uv0.empty()) mesh_.uv0.push_back({0, 0});  // keep uv0 parallel once it exists
      }
      return vertexOfObj_[c.v];
    }
    const uint64_t key = (uint64_t(c.v) << 32) | uint64_t(c.vt);
    auto [it, inserted] = splitIndex_.emplace(key, uint32_t(mesh_.positions.size()));
    if (inserted) {
      mesh_.positions.push_back(objPositions_[c.v]);
      objOfVertex_.push_back(c.v);
      mesh_.uv0.resize(mesh_.positions.size() - 1, {0, 0});
      // OBJ's v grows upwards; glTF's t (which the voxelizer samples) downwards.
      mesh_.uv0.push_back({texcoords_[size_t(c.vt)][0], 1.0f - texcoords_[size_t(c.vt)][1]});
    }
    return it->second;
  }

  const std::string& name_;
  const MeshReadOptions& options_;
  std::vector<std::string>& warnings_;
  const std::string& baseDir_;
  Mesh mesh_;
  std::vector<std::array<double, 3>> objPositions_;
  // Per obj position once any "v" line has a colour (empty until then: 16
  // bytes a vertex that a file without colours never needs), white for the
  // lines without one.
  std::vector<std::array<float, 4>> objColors_;
  std::vector<std::array<float, 2>> texcoords_;
  std::vector<uint32_t> vertexOfObj_;  // obj position -> mesh vertex (no texcoord), UINT32_MAX: none yet
  std::vector<uint32_t> objOfVertex_;  // mesh vertex -> obj position (for vertex colours)
  std::unordered_map<uint64_t, uint32_t> splitIndex_;  // (v, vt) -> mesh vertex
  std::unordered_map<std::string, uint32_t> materialByName_;
  std::unordered_map<uint32_t, size_t> undefinedMaterials_;  // white until a library defines them: material -> line
  int64_t currentMaterial_ = -1;  // none chosen yet: faces use the default material
  int64_t defaultMaterial_ = -1;
  uint32_t currentPart_ = 0;
  std::vector<Corner> face_;  // the corners of the face being read
  std::vector<uint32_t> cornerVertex_;             // face_'s mesh vertices
  std::vector<std::array<double, 3>> cornerAt_;    // face_'s positions
  std::vector<std::array<uint32_t, 3>> polygon_;   // its triangles, as corner indices
  PolygonScratch polygonScratch_;
  bool anyVertexColor_ = false;
  size_t invalidVertices_ = 0, firstInvalidLine_ = 0, firstInvalidVertex_ = 0;  // NaN/Inf "v" lines
  size_t shortFaces_ = 0, firstShortFaceLine_ = 0;  // "f" lines of fewer than 3 corners, dropped
};

/// One line in the serial pass, as the single pass reads it.
void parseLine(ObjParser& obj, Cursor& c) {
  c.skipSpaces();
  if (c.atEol() || *c.p == '#') return;
  const std::string_view key = c.word();
  if (key == "v") obj.vertex(c);
  else if (key == "vt") obj.texcoord(c);
  else if (key == "f") obj.face(c);
  else if (key == "o" || key == "g") obj.part(c);
  else if (key == "usemtl") obj.useMaterial(c);
  else if (key == "mtllib") obj.materialLibraries(c);
}

/// What the parallel pre-pass makes of one chunk of whole lines. Each line is
/// skipped (blank or a comment), read here (a plain "v x y z" or an "f" of
/// plain vertex indices, optionally with "//normal"), or left to the serial
/// pass (every other keyword, which parseLine handles or ignores, and any
/// line that does not read cleanly, so its error message is the single pass's).
struct ObjChunk {
  static constexpr uint8_t kSkip = 0, kSerial = 1, kVertex = 2;  // 3..255: a face of that many corners
  const char* begin = nullptr;
  const char* end = nullptr;
  std::vector<uint8_t> kind;                    // per line
  std::vector<const char*> serialLines;         // where each kSerial line starts
  std::vector<std::array<double, 3>> vertices;  // kVertex lines, in order
  std::vector<int32_t> corners;                 // face lines' indices as written, in order
};

/// `number` without throwing: false where it would throw.
bool tryNumber(Cursor& c, double& v) {
  c.skipSpaces();
  auto [ptr, ec] = parseDoubleAllowingPlus(c.p, c.end, v);
  if (ec != std::errc()) return false;
  c.p = ptr;
  return true;
}

/// A "v" line's rest, if it is exactly three numbers (then end of line or a comment).
bool tryPlainVertex(Cursor& c, std::array<double, 3>& p) {
  for (int k = 0; k < 3; ++k)
    if (!tryNumber(c, p[size_t(k)])) return false;
  c.skipSpaces();
  return c.atEol() || *c.p == '#';
}

/// An "f" line's rest, if every corner is "v" or "v//vn" with v in int32 and
/// 3 to 255 corners; the indices are appended to `out`.
bool tryPlainFace(Cursor& c, std::vector<int32_t>& out, size_t& n) {
  n = 0;
  while (true) {
    c.skipSpaces();
    if (c.atEol() || *c.p == '#') break;
    int64_t v = 0;
    auto [ptr, ec] = parseInt64(c.p, c.end, v);
    if (ec != std::errc() || v < INT32_MIN || v > INT32_MAX) return false;
    c.p = ptr;
    if (c.p < c.end && *c.p == '/') {
      if (c.p + 1 >= c.end || c.p[1] != '/') return false;  // a texture coordinate: the serial pass
      c.p += 2;
      int64_t vn = 0;
      auto [p3, e3] = parseInt64(c.p, c.end, vn);
      if (e3 == std::errc()) c.p = p3;
    }
    if (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\n' && *c.p != '\r' && *c.p != '#') return false;
    out.push_back(int32_t(v));
    if (++n > 255) return false;
  }
  return n >= 3;
}

void prepassChunk(ObjChunk& chunk) {
  Cursor c{chunk.begin, chunk.end};
  while (c.p < c.end) {
    const char* line = c.p;
    c.skipSpaces();
    uint8_t kind = ObjChunk::kSkip;
    if (!c.atEol() && *c.p != '#') {
      const std::string_view key = c.word();
      if (key == "v") {
        std::array<double, 3> p;
        if (tryPlainVertex(c, p)) {
          chunk.vertices.push_back(p);
          kind = ObjChunk::kVertex;
        } else {
          kind = ObjChunk::kSerial;
        }
      } else if (key == "f") {
        const size_t before = chunk.corners.size();
        size_t n = 0;
        if (tryPlainFace(c, chunk.corners, n)) {
          kind = uint8_t(n);
        } else {
          chunk.corners.resize(before);
          kind = ObjChunk::kSerial;
        }
      } else {
        kind = ObjChunk::kSerial;  // parseLine decides what it is (or ignores it): one list of keywords
      }
    }
    if (kind == ObjChunk::kSerial) chunk.serialLines.push_back(line);
    chunk.kind.push_back(kind);
    c.nextLine();
  }
}

/// Chunks of about `chunkBytes` of whole lines (the count depends on the file only).
std::vector<ObjChunk> splitIntoChunks(const char* data, size_t size, size_t chunkBytes) {
  std::vector<ObjChunk> chunks;
  for (const char* b = data; b < data + size;) {
    const char* e = data + std::min(size, size_t(b - data) + std::max<size_t>(1, std::min(chunkBytes, size)));
    if (e < data + size) {
      const void* nl = std::memchr(e, '\n', size_t(data + size - e));
      e = nl ? static_cast<const char*>(nl) + 1 : data + size;
    }
    chunks.emplace_back();
    chunks.back().begin = b;
    chunks.back().end = e;
    b = e;
  }
  return chunks;
}

/// Where `p` (a backslash) ends its line: the backslash is followed only by
/// spaces, tabs or '\r' up to the end of the line or of the file.
bool endsLine(const char* p, const char* end) {
  for (++p; p < end && *p != '\n'; ++p)
    if (*p != ' ' && *p != '\t' && *p != '\r') return false;
  return true;
}

/// OBJ's line continuation: a line ending in a backslash goes on on the next
/// line (the format's specification; some exporters break long face lines so).
/// Returns false when `data` has none. Else `joined` is the text with every
/// continued line joined into one, the backslash and line break turned into
/// spaces, and the line breaks this removes put back after the joined line, so
/// every later line keeps its number in messages (a joined line has the number
/// of its first part). A comment line is never continued: one ending in a
/// Windows path ("# C:\models\") would swallow the line after it.
bool joinContinuedLines(const char* data, size_t size, std::string& joined) {
  const char* end = data + size;
  bool any = false;
  for (const char* p = data; (p = static_cast<const char*>(std::memchr(p, '\\', size_t(end - p)))) != nullptr; ++p)
    if (endsLine(p, end)) {
      any = true;
      break;
    }
  if (!any) return false;
  joined.clear();
  joined.reserve(size + 64);
  size_t pendingBreaks = 0;  // line breaks removed from the logical line being copied
  bool continuing = false;   // the current physical line continues a logical line
  for (const char* b = data; b < end;) {
    const char* nl = static_cast<const char*>(std::memchr(b, '\n', size_t(end - b)));
    const char* e = nl ? nl : end;
    const char* first = b;
    while (first < e && (*first == ' ' || *first == '\t')) ++first;
    const bool comment = !continuing && first < e && *first == '#';
    const char* last = e;
    while (last > b && (last[-1] == ' ' || last[-1] == '\t' || last[-1] == '\r')) --last;
    if (!comment && last > b && last[-1] == '\\') {
      joined.append(b, size_t(last - 1 - b));
      joined += ' ';
      ++pendingBreaks;
      continuing = true;
    } else {
      joined.append(b, size_t(e - b));
      if (nl) joined += '\n';
      joined.append(pendingBreaks, '\n');
      pendingBreaks = 0;
      continuing = false;
    }
    b = nl ? nl + 1 : end;
  }
  if (pendingBreaks) joined.append(pendingBreaks, '\n');  // the file ended inside a continued line
  return true;
}

}  // namespace

Mesh parseObj(const char* data, size_t size, const std::string& name, const MeshReadOptions& options,
              std::vector<std::string>& warnings, const std::string& baseDir, size_t chunkBytes) {
  const size_t bom = utf8BomLength(data, size);
  data += bom, size -= bom;
  std::string lf, joined;
  if (loneCrAsLf(data, size, lf)) data = lf.data(), size = lf.size();
  if (joinContinuedLines(data, size, joined)) data = joined.data(), size = joined.size();
  ObjParser obj(name, options, warnings, baseDir);
  obj.reserveFor(data, size);
  std::vector<ObjChunk> chunks = splitIntoChunks(data, size, chunkBytes);
  // Each chunk's numbers on TBB's threads (capped at --threads by the CLI), a
  // few chunks ahead of the in-order pass, which frees each chunk's arrays
  // for the next ones: the pre-pass adds a few MB, not a copy of the mesh.
  size_t line = 1;
  orderedPipeline(
      chunks.size(), 0, 2 * size_t(workerCount(0)), [&](size_t i) { prepassChunk(chunks[i]); },
      [&](size_t i) {
        ObjChunk& chunk = chunks[i];
        size_t vertex = 0, corner = 0, serial = 0;
        for (const uint8_t kind : chunk.kind) {
          if (kind == ObjChunk::kVertex) {
            obj.parsedVertex(chunk.vertices[vertex++], line);
          } else if (kind >= 3) {
            obj.parsedFace(chunk.corners.data() + corner, kind, line);
            corner += kind;
          } else if (kind == ObjChunk::kSerial) {
            Cursor c{chunk.serialLines[serial++], chunk.end, line};
            parseLine(obj, c);
          }
          ++line;
        }
        chunk = ObjChunk();
      });
  return obj.finish();
}

}  // namespace vox
