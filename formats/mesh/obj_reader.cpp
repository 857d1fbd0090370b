// Wavefront OBJ + MTL. Hand-written rather than a library: one pass over the
// bytes with std::from_chars, no per-line allocation, which is what reaching
// 100 MB/s takes.
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <unordered_map>

#include "formats/core/file_util.h"
#include "libvox/core/color.h"
#include "formats/mesh/mesh_input.h"
#include "libvox/core/error.h"

#include <stb/stb_image.h>

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

[[noreturn]] void bad(const std::string& name, size_t line, const std::string& what) {
  throwBadInput(name + ":" + std::to_string(line) + ": " + what);
}

double number(Cursor& c, const std::string& name, const char* what) {
  c.skipSpaces();
  double v = 0;
  // from_chars rejects a leading '+', which some exporters write.
  const char* b = c.p < c.end && *c.p == '+' ? c.p + 1 : c.p;
  auto [ptr, ec] = std::from_chars(b, c.end, v);
  if (ec != std::errc() || ptr == b) bad(name, c.line, std::string("expected a number for ") + what);
  c.p = ptr;
  return v;
}

/// True when `path` names a regular file; never throws (a name too long or
/// otherwise invalid is simply not a file).
bool isFile(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

MeshTexture loadTexture(const std::string& path, const std::string& mtlName, size_t line) {
  if (!isFile(path))
    throwBadInput(mtlName + ":" + std::to_string(line) + ": map_Kd " + path +
                  ": the texture file is missing; restore it or remove the map_Kd line");
  const std::string bytes = readFileBytes(path);
  int w = 0, h = 0, n = 0;
  stbi_uc* px = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &w, &h, &n, 4);
  if (!px) throwBadInput(mtlName + ":" + std::to_string(line) + ": map_Kd " + path + ": cannot decode the image (" +
                         stbi_failure_reason() + ")");
  MeshTexture t;
  t.width = uint32_t(w);
  t.height = uint32_t(h);
  t.rgba.assign(px, px + size_t(w) * h * 4);
  stbi_image_free(px);
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

/// Parses an MTL file into `mesh.materials` (names -> index in `byName`).
void parseMtl(const std::string& path, Mesh& mesh, std::unordered_map<std::string, uint32_t>& byName,
              const MeshReadOptions& options, std::vector<std::string>& warnings) {
  const std::string text = readFileBytes(path);
  mesh.filesRead.push_back(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  Cursor c{text.data(), text.data() + text.size()};
  int current = -1;
  while (c.p < c.end) {
    const std::string_view key = c.word();
    if (key == "newmtl") {
      MeshMaterial m;
      m.name = c.rest();
      current = int(mesh.materials.size());
      byName[m.name] = uint32_t(current);
      mesh.materials.push_back(m);
    } else if (key == "Kd" && current >= 0) {
      // OBJ/MTL colours are conventionally linear reflectances.
      for (int k = 0; k < 3; ++k) mesh.materials[current].baseColorFactor[k] = float(number(c, path, "Kd"));
    } else if (key == "map_Kd" && current >= 0) {
      std::string file = c.rest();
      // Options such as "-bm 1 file.png" precede the file name: take the last word.
      if (const size_t sp = file.find_last_of(" \t"); sp != std::string::npos) file = file.substr(sp + 1);
      const std::string full = resolvePath(dir, file);
      if (options.ignoreMissingMaterials && !isFile(full)) {
        warnings.push_back(path + ":" + std::to_string(c.line) + ": map_Kd " + file +
                           ": the texture file is missing; material '" + mesh.materials[current].name +
                           "' is left untextured");
        c.nextLine();
        continue;
      }
      mesh.textures.push_back(loadTexture(full, path, c.line));
      mesh.filesRead.push_back(full);
      mesh.materials[current].texture = int(mesh.textures.size() - 1);
    }
    c.nextLine();
  }
}

}  // namespace

Mesh parseObj(const char* data, size_t size, const std::string& name, const MeshReadOptions& options,
              std::vector<std::string>& warnings, const std::string& baseDir) {
  Mesh mesh;
  std::vector<std::array<float, 2>> texcoords;
  struct Corner {
    uint32_t v;
    int64_t vt;  // -1: none
  };
  // Vertices that carry a texture coordinate are split per (v, vt) pair.
  std::unordered_map<uint64_t, uint32_t> splitIndex;
  std::vector<std::array<double, 3>> objPositions;
  std::unordered_map<std::string, uint32_t> materialByName;
  int64_t currentMaterial = -1;  // none chosen yet: faces use an unnamed white material
  int64_t defaultMaterial = -1;
  uint32_t currentPart = 0;
  mesh.parts.push_back({"", std::filesystem::path(name).filename().string()});
  std::vector<Corner> face;
  std::vector<uint32_t> vertexOfObj;  // objPositions index -> mesh vertex (no texcoord)
  std::vector<uint32_t> objOfVertex;  // mesh vertex -> objPositions index (for vertex colours)
  // "v x y z r g b [a]" (MeshLab, ZBrush and most scanners): colours in [0, 1]
  // written from 8-bit sRGB, so they are decoded to linear like PLY bytes.
  std::vector<std::array<float, 4>> objColors;
  bool anyVertexColor = false;
  size_t invalidVertices = 0, firstInvalidLine = 0, firstInvalidVertex = 0;  // NaN/Inf "v" lines
  {
    // Reserve from a count of "v " and "f " lines (memchr runs at GB/s): growing
    // these arrays by doubling copied and faulted in twice their final size,
    // which cost more than parsing the numbers.
    size_t vLines = 0, fLines = 0;
    for (const char* q = data; q < data + size;) {
      if (q + 1 < data + size && q[1] == ' ') vLines += q[0] == 'v', fLines += q[0] == 'f';
      const void* nl = std::memchr(q, '\n', size_t(data + size - q));
      q = nl ? static_cast<const char*>(nl) + 1 : data + size;
    }
    objPositions.reserve(vLines);
    objColors.reserve(vLines);
    vertexOfObj.reserve(vLines);
    objOfVertex.reserve(vLines);
    mesh.positions.reserve(vLines);
    mesh.triangles.reserve(fLines);
    mesh.triangleMaterial.reserve(fLines);
    mesh.trianglePart.reserve(fLines);
  }

  auto resolve = [&](int64_t idx, size_t count, size_t line, const char* what) -> uint32_t {
    const int64_t i = idx < 0 ? int64_t(count) + idx : idx - 1;
    if (idx == 0 || i < 0 || i >= int64_t(count))
      bad(name, line, std::string("face refers to ") + what + " " + std::to_string(idx) + " but " +
                          std::to_string(count) + " are defined so far");
    return uint32_t(i);
  };
  auto meshVertex = [&](const Corner& c) -> uint32_t {
    if (c.vt < 0) {
      if (vertexOfObj[c.v] == UINT32_MAX) {
        vertexOfObj[c.v] = uint32_t(mesh.positions.size());
        mesh.positions.push_back(objPositions[c.v]);
        objOfVertex.push_back(c.v);
        if (!mesh.uv0.empty()) mesh.uv0.push_back({0, 0});  // keep uv0 parallel once it exists
      }
      return vertexOfObj[c.v];
    }
    const uint64_t key = (uint64_t(c.v) << 32) | uint64_t(c.vt);
    auto [it, inserted] = splitIndex.emplace(key, uint32_t(mesh.positions.size()));
    if (inserted) {
      mesh.positions.push_back(objPositions[c.v]);
      objOfVertex.push_back(c.v);
      mesh.uv0.resize(mesh.positions.size() - 1, {0, 0});
      // OBJ's v grows upwards; glTF's t (which the voxelizer samples) downwards.
      mesh.uv0.push_back({texcoords[size_t(c.vt)][0], 1.0f - texcoords[size_t(c.vt)][1]});
    }
    return it->second;
  };

  Cursor c{data, data + size};
  while (c.p < c.end) {
    c.skipSpaces();
    if (c.atEol() || *c.p == '#') {
      c.nextLine();
      continue;
    }
    const std::string_view key = c.word();
    if (key == "v") {
      std::array<double, 3> p;
      for (int k = 0; k < 3; ++k) p[k] = number(c, name, "a vertex coordinate");
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        if (!invalidVertices++) firstInvalidLine = c.line, firstInvalidVertex = objPositions.size() + 1;
      }
      objPositions.push_back(p);
      vertexOfObj.push_back(UINT32_MAX);
      // Optional trailing numbers: w (1 value, ignored), r g b (3) or r g b a (4).
      double extra[4];
      int n = 0;
      for (c.skipSpaces(); !c.atEol() && *c.p != '#'; c.skipSpaces()) {
        if (n == 4) bad(name, c.line, "a vertex has more than 7 numbers; expected x y z [w] or x y z r g b [a]");
        extra[n++] = number(c, name, "a vertex colour");
      }
      std::array<float, 4> color{1, 1, 1, 1};
      if (n == 2) bad(name, c.line, "a vertex has 5 numbers; expected x y z [w] or x y z r g b [a]");
      if (n >= 3) {
        for (int k = 0; k < n; ++k)
          if (!(extra[k] >= 0 && extra[k] <= 1))
            bad(name, c.line, "vertex colour component " + std::to_string(extra[k]) + " is outside [0, 1]");
        for (int k = 0; k < 3; ++k) color[size_t(k)] = srgbToLinear(extra[k]);
        if (n == 4) color[3] = float(extra[3]);
        anyVertexColor = true;
      }
      objColors.push_back(color);
    } else if (key == "vt") {
      const float s = float(number(c, name, "a texture coordinate"));
      c.skipSpaces();
      const float t = c.atEol() ? 0.0f : float(number(c, name, "a texture coordinate"));
      texcoords.push_back({s, t});
    } else if (key == "f") {
      face.clear();
      while (true) {
        c.skipSpaces();
        if (c.atEol()) break;
        int64_t v = 0, vt = 0;
        auto [ptr, ec] = std::from_chars(c.p, c.end, v);
        if (ec != std::errc()) bad(name, c.line, "expected a vertex index in the face");
        c.p = ptr;
        int64_t vtIndex = -1;
        if (c.p < c.end && *c.p == '/') {
          ++c.p;
          if (c.p < c.end && *c.p != '/') {
            auto [p2, e2] = std::from_chars(c.p, c.end, vt);
            if (e2 != std::errc()) bad(name, c.line, "expected a texture coordinate index after '/'");
            c.p = p2;
            vtIndex = resolve(vt, texcoords.size(), c.line, "texture coordinate");
          }
          if (c.p < c.end && *c.p == '/') {  // normal index: read and ignore
            ++c.p;
            int64_t vn = 0;
            auto [p3, e3] = std::from_chars(c.p, c.end, vn);
            if (e3 == std::errc()) c.p = p3;
          }
        }
        face.push_back({resolve(v, objPositions.size(), c.line, "vertex"), vtIndex});
        if (c.p < c.end && *c.p != ' ' && *c.p != '\t' && *c.p != '\n' && *c.p != '\r')
          bad(name, c.line, "unexpected character in a face");
      }
      if (face.size() < 3) bad(name, c.line, "a face needs at least 3 vertices");
      if (currentMaterial < 0) {
        if (defaultMaterial < 0) {
          defaultMaterial = int64_t(mesh.materials.size());
          mesh.materials.push_back({"", {1, 1, 1, 1}, -1, 0});
        }
        currentMaterial = defaultMaterial;
      }
      const uint32_t first = meshVertex(face[0]);
      for (size_t k = 1; k + 1 < face.size(); ++k) {  // fan triangulation
        mesh.triangles.push_back({first, meshVertex(face[k]), meshVertex(face[k + 1])});
        mesh.triangleMaterial.push_back(uint32_t(currentMaterial));
        mesh.trianglePart.push_back(currentPart);
      }
    } else if (key == "o" || key == "g") {
      const std::string n = c.rest();
      mesh.parts.push_back({n, std::filesystem::path(name).filename().string()});
      currentPart = uint32_t(mesh.parts.size() - 1);
    } else if (key == "usemtl") {
      const std::string n = c.rest();
      auto it = materialByName.find(n);
      if (it == materialByName.end()) {
        // A material no MTL defines: keep its name (for --classes), white.
        mesh.materials.push_back({n, {1, 1, 1, 1}, -1, 0});
        it = materialByName.emplace(n, uint32_t(mesh.materials.size() - 1)).first;
        warnings.push_back(name + ":" + std::to_string(c.line) + ": material '" + n + "' is not defined in any mtllib");
      }
      currentMaterial = it->second;
    } else if (key == "mtllib") {
      // "mtllib a.mtl b.mtl" names several files; a single name may contain spaces.
      const std::string all = c.rest();
      std::vector<std::string> files{all};
      if (!isFile(resolvePath(baseDir, all))) {
        files.clear();
        for (size_t b = 0; b < all.size();) {
          const size_t e = std::min(all.find_first_of(" \t", b), all.size());
          if (e > b) files.push_back(all.substr(b, e - b));
          b = e + 1;
        }
      }
      for (const std::string& file : files) {
        const std::string full = resolvePath(baseDir, file);
        if (options.ignoreMissingMaterials && !isFile(full)) {
          warnings.push_back(name + ":" + std::to_string(c.line) + ": mtllib " + file +
                             ": the material library is missing; its materials are white");
          continue;
        }
        try {
          parseMtl(full, mesh, materialByName, options, warnings);
        } catch (const Error& e) {
          throwBadInput(name + ":" + std::to_string(c.line) + ": mtllib " + file + ": " + e.what());
        }
      }
    }
    c.nextLine();
  }
  if (mesh.materials.empty()) mesh.materials.push_back({"", {1, 1, 1, 1}, -1, 0});
  if (!mesh.uv0.empty()) mesh.uv0.resize(mesh.positions.size(), {0, 0});
  if (anyVertexColor) {  // vertices written without a colour are white
    mesh.colors.resize(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) mesh.colors[i] = objColors[objOfVertex[i]];
  }
  // Name the first bad "v" line (the generic check below only knows mesh vertex numbers).
  if (invalidVertices && !options.dropInvalid)
    bad(name, firstInvalidLine,
        std::to_string(invalidVertices) + " vertices have NaN or infinite coordinates (the first is vertex " +
            std::to_string(firstInvalidVertex) + ", on this line); fix the file or pass --drop-invalid to drop their "
            "triangles");
  checkFinite(mesh, name, options, warnings);
  return mesh;
}

}  // namespace vox
