#include "libvox/mesh/mesh.h"

#include <algorithm>

namespace vox {

bool Mesh::hasColor() const {
  if (!colors.empty()) return true;
  for (const MeshMaterial& m : materials) {
    if (m.texture >= 0) return true;
    if (m.baseColorFactor[0] != 1 || m.baseColorFactor[1] != 1 || m.baseColorFactor[2] != 1) return true;
  }
  return false;
}

void Mesh::append(const Mesh& other) {
  const uint32_t vbase = uint32_t(positions.size());
  const uint32_t mbase = uint32_t(materials.size());
  const uint32_t pbase = uint32_t(parts.size());
  const int tbase = int(textures.size());
  const size_t oldVerts = positions.size();
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  for (const auto& t : other.triangles) triangles.push_back({t[0] + vbase, t[1] + vbase, t[2] + vbase});
  for (uint32_t m : other.triangleMaterial) triangleMaterial.push_back(m + mbase);
  for (uint32_t p : other.trianglePart) trianglePart.push_back(p + pbase);
  // Per-vertex arrays stay parallel to positions: pad whichever side lacks them.
  auto mergeAttr = [&](auto& mine, const auto& theirs, auto fill) {
    if (mine.empty() && theirs.empty()) return;
    mine.resize(oldVerts, fill);
    if (theirs.empty()) mine.resize(positions.size(), fill);
    else mine.insert(mine.end(), theirs.begin(), theirs.end());
  };
  mergeAttr(uv0, other.uv0, std::array<float, 2>{0, 0});
  mergeAttr(uv1, other.uv1, std::array<float, 2>{0, 0});
  mergeAttr(colors, other.colors, std::array<float, 4>{1, 1, 1, 1});
  mergeAttr(fileVertex, other.fileVertex, uint32_t(0));
  // Vertices without a run of their own (a mesh made in memory) stay counted from 1 within their mesh.
  if (!other.vertexRuns.empty() && vertexRuns.empty() && oldVerts > 0) vertexRuns.push_back({0, "", "vertex", 1, " (counted from 1)"});
  if (other.vertexRuns.empty() && !vertexRuns.empty() && !other.positions.empty())
    vertexRuns.push_back({oldVerts, "", "vertex", 1, " (counted from 1)"});
  for (MeshVertexRun run : other.vertexRuns) {
    run.firstVertex += oldVerts;
    vertexRuns.push_back(std::move(run));
  }
  for (MeshMaterial m : other.materials) {
    if (m.texture >= 0) m.texture += tbase;
    materials.push_back(m);
  }
  textures.insert(textures.end(), other.textures.begin(), other.textures.end());
  parts.insert(parts.end(), other.parts.begin(), other.parts.end());
  filesRead.insert(filesRead.end(), other.filesRead.begin(), other.filesRead.end());
}

std::string Mesh::describeVertex(size_t i, bool withFile) const {
  auto after = std::upper_bound(vertexRuns.begin(), vertexRuns.end(), i,
                                [](size_t v, const MeshVertexRun& run) { return v < run.firstVertex; });
  if (after == vertexRuns.begin()) return "vertex " + std::to_string(i + 1) + " (counted from 1)";
  const MeshVertexRun& run = *(after - 1);
  const int64_t n = i < fileVertex.size() && fileVertex[i] ? int64_t(fileVertex[i])
                                                           : run.firstNumber + int64_t(i - run.firstVertex);
  return (run.file.empty() || !withFile ? "" : run.file + ": ") + run.what + " " + std::to_string(n) + run.note;
}

size_t Mesh::keepTriangles(const std::vector<bool>& keep, std::vector<uint8_t>* alongside) {
  const bool material = !triangleMaterial.empty(), part = !trianglePart.empty();
  size_t kept = 0;
  for (size_t t = 0; t < triangles.size(); ++t) {
    if (!keep[t]) continue;
    triangles[kept] = triangles[t];
    if (material) triangleMaterial[kept] = triangleMaterial[t];
    if (part) trianglePart[kept] = trianglePart[t];
    if (alongside) (*alongside)[kept] = (*alongside)[t];
    ++kept;
  }
  const size_t dropped = triangles.size() - kept;
  triangles.resize(kept);
  if (material) triangleMaterial.resize(kept);
  if (part) trianglePart.resize(kept);
  if (alongside) alongside->resize(kept);
  return dropped;
}

}  // namespace vox
