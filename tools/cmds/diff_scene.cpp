// vox diff of scenes and pyramids (.vdb): the report of vox::diffScenes, per
// level for pyramids.
#include <algorithm>
#include <cstdio>
#include <future>
#include <iostream>
#include <optional>
#include <sstream>

#include "formats/core/file_util.h"
#include "formats/core/json_diff.h"
#include "formats/core/json_text.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_memory.h"
#include "libvox/core/error.h"
#include "libvox/core/memory_budget.h"
#include "libvox/scene/scene_diff.h"
#include "tools/cli/cli.h"
#include "tools/cmds/diff_common.h"

namespace voxcli {

namespace {

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

nlohmann::json valuesJson(const vox::VoxelValues& v) {
  if (!v.occupied) return nullptr;
  nlohmann::json votes = nlohmann::json::object();
  for (const vox::ClassVotes& c : v.votes) votes[std::to_string(c.classId)] = c.votes;
  nlohmann::json j = {{"surface", v.surface}, {"votes", votes}};
  j["color"] = v.color ? nlohmann::json{v.color->r, v.color->g, v.color->b} : nlohmann::json(nullptr);
  return j;
}

// Where a voxel is in the world: in the scene it is occupied in (a voxel only
// in B is placed by B's header, which may differ from A's), and in both when
// both have it and their placements differ.
struct VoxelWorld {
  std::array<double, 3> at;
  std::optional<std::array<double, 3>> inB;  // B's position, when it is not `at`
};
VoxelWorld voxelWorld(const vox::VoxelDiffExample& e, const vox::SceneHeader& ha, const vox::SceneHeader& hb) {
  if (!e.a.occupied) return {vox::voxelCentreWorld(hb, e.at), std::nullopt};
  VoxelWorld w{vox::voxelCentreWorld(ha, e.at), std::nullopt};
  if (e.b.occupied && vox::voxelCentreWorld(hb, e.at) != w.at) w.inB = vox::voxelCentreWorld(hb, e.at);
  return w;
}

nlohmann::json exampleJson(const vox::VoxelDiffExample& e, const vox::SceneHeader& ha, const vox::SceneHeader& hb) {
  const VoxelWorld w = voxelWorld(e, ha, hb);
  nlohmann::json j = {{"voxel", coordJson(e.at)}, {"world", {w.at[0], w.at[1], w.at[2]}}, {"magnitude", e.magnitude},
                      {"a", valuesJson(e.a)},      {"b", valuesJson(e.b)}};
  if (w.inB) j["world_b"] = {(*w.inB)[0], (*w.inB)[1], (*w.inB)[2]};
  return j;
}

std::string exampleText(const vox::VoxelDiffExample& e, const vox::SceneHeader& ha, const vox::SceneHeader& hb) {
  const VoxelWorld w = voxelWorld(e, ha, hb);
  auto pos = [](const std::array<double, 3>& p) { return "(" + num(p[0]) + ", " + num(p[1]) + ", " + num(p[2]) + ")"; };
  return "voxel " + vox::toString(e.at) + " world " + pos(w.at) + (w.inB ? " in A, " + pos(*w.inB) + " in B" : "") +
         ": A " + vox::describeVoxel(e.a) + " | B " + vox::describeVoxel(e.b);
}

/// "32 x 32 x 32", or "32 x 32 x 32 vs 64 x 64 x 64" when the scenes' dims differ.
std::string dimsText(const vox::SceneHeader& ha, const vox::SceneHeader& hb) {
  return vox::toString(ha.dims) + (ha.dims == hb.dims ? "" : " vs " + vox::toString(hb.dims));
}

nlohmann::json sceneDiffJson(const vox::SceneDiff& d, const vox::SceneHeader& h, const vox::SceneHeader& hb,
                             const DiffOptions& o) {
  nlohmann::json header = nlohmann::json::array(), classes = nlohmann::json::array();
  for (const auto& f : d.header) header.push_back({{"field", f.field}, {"a", f.a}, {"b", f.b}});
  for (const auto& c : d.classes) classes.push_back({{"id", c.id}, {"a", c.a}, {"b", c.b}});
  nlohmann::json j = {{"same", d.same()},
                      {"header_differs", !d.header.empty() || !d.classes.empty()},
                      {"header_note", d.header.empty() ? (d.classes.empty() ? "" : "class table differs")
                                                       : d.header[0].field + " " + d.header[0].a + " vs " + d.header[0].b},
                      {"header", header},
                      {"classes", classes},
                      {"dims_a", {h.dims.x, h.dims.y, h.dims.z}},
                      {"dims_b", {hb.dims.x, hb.dims.y, hb.dims.z}},
                      {"voxels_a", d.voxelsA},
                      {"voxels_b", d.voxelsB},
                      {"voxels_compared", d.voxelsCompared},
                      {"voxels_differing", d.voxelsDiffering},
                      {"only_in_a", d.onlyInA},
                      {"only_in_b", d.onlyInB},
                      {"tolerances", {{"votes", o.votesTolerance}, {"color", o.colorTolerance}}}};
  nlohmann::json kinds = nlohmann::json::object();
  for (int k = 0; k < vox::kVoxelDiffKinds; ++k) {
    const vox::VoxelKindDiff& kd = d.kinds[size_t(k)];
    nlohmann::json e = {{"count", kd.count}};
    e["first"] = kd.first ? exampleJson(*kd.first, h, hb) : nlohmann::json(nullptr);
    e["worst"] = kd.worst ? exampleJson(*kd.worst, h, hb) : nlohmann::json(nullptr);
    kinds[vox::voxelDiffKindName(vox::VoxelDiffKind(k))] = e;
  }
  j["kinds"] = kinds;
  if (d.first) {
    nlohmann::json f = exampleJson(*d.first, h, hb);
    f["values"] = vox::describeVoxel(d.first->a) + " vs " + vox::describeVoxel(d.first->b);
    j["first_difference"] = f;
  }
  return j;
}

std::string sceneDiffText(const vox::SceneDiff& d, const vox::SceneHeader& h, const vox::SceneHeader& hb,
                          const DiffOptions& o, const std::string& indent) {
  std::ostringstream s;
  for (const auto& f : d.header) s << indent << "header " << f.field << ": " << f.a << " vs " << f.b << "\n";
  for (const auto& c : d.classes) s << indent << "class " << int(c.id) << ": " << c.a << " vs " << c.b << "\n";
  s << indent << "voxels: " << d.voxelsCompared << " compared (A " << d.voxelsA << ", B " << d.voxelsB << "), "
    << d.voxelsDiffering << " differ\n";
  if (d.voxelsDiffering == 0) return s.str();
  for (int k = 0; k < vox::kVoxelDiffKinds; ++k) {
    const auto kind = vox::VoxelDiffKind(k);
    const vox::VoxelKindDiff& kd = d.kinds[size_t(k)];
    char name[16];
    std::snprintf(name, sizeof name, "%-10s", vox::voxelDiffKindName(kind));
    s << indent << "  " << name << " " << kd.count;
    if (kind == vox::VoxelDiffKind::Occupancy) s << " (only in A " << d.onlyInA << ", only in B " << d.onlyInB << ")";
    if (kind == vox::VoxelDiffKind::Votes) s << " (tolerance " << counted(o.votesTolerance, "vote", "votes") << " per class)";
    if (kind == vox::VoxelDiffKind::Color) s << " (tolerance " << num(o.colorTolerance) << " per linear channel)";
    s << "\n";
    if (kd.first) s << indent << "    first " << exampleText(*kd.first, h, hb) << "\n";
    if (kd.worst && kd.count > 1) {
      s << indent << "    worst " << exampleText(*kd.worst, h, hb);
      if (kind == vox::VoxelDiffKind::Votes)
        s << " (" << num(kd.worst->magnitude) << (kd.worst->magnitude == 1 ? " vote)" : " votes)");
      if (kind == vox::VoxelDiffKind::Color) s << " (" << num(kd.worst->magnitude) << ")";
      s << "\n";
    }
  }
  if (d.first)
    s << indent << "first difference at voxel " << vox::toString(d.first->at)
      << " (smallest w, v, u): " << vox::describeVoxel(d.first->a) << " vs " << vox::describeVoxel(d.first->b)
      << "\n";
  return s.str();
}

vox::SceneDiffOptions sceneOptions(const DiffOptions& o) {
  vox::SceneDiffOptions so;
  so.votesTolerance = o.votesTolerance;
  so.colorTolerance = o.colorTolerance;
  so.ignoreSources = o.ignoreSources;
  so.threads = o.threads;
  return so;
}

/// The memory guard of a comparison: both files are read at once and stay
/// resident together while they are compared, so they are checked as one,
/// from the topology of each (leaf counts), before either is read; each
/// reader's own check sees only its file. Besides both scenes' grids: both
/// files, mapped while they are read (at once), the two reading threads'
/// malloc arenas (about 10 MiB, measured), and the comparison's leaf
/// origins of both occupancy grids of a level (12 bytes each; counted for
/// every bool grid of both files, a bound). Measured against /usr/bin/time:
/// docs/reliability.md "Memory".
void checkDiffMemory(const DiffOptions& o) {
  vox::MemoryEstimate e;
  e.add("resident before reading", vox::residentBytesNow());
  double boolLeaves = 0, fileBytes = 0;
  for (const std::string* path : {&o.a, &o.b}) {
    const vox::VdbFrame frame = vox::vdbTopologyFrame(*path);
    e.add(std::string(path == &o.a ? "A's" : "B's") + " grids", vox::sceneGridBytes(frame, false, vox::SceneReadForm::Trees));
    for (const vox::VdbGridFrame& g : frame.grids)
      if (g.checked && g.instanceParent.empty() && g.type.find("_bool_") != std::string::npos)
        boolLeaves += double(g.leafCount);
    fileBytes += double(std::max<int64_t>(0, vox::fileSizeOrMinusOne(*path)));
  }
  e.add("both files, mapped while read", fileBytes);
  e.add("two reading threads", uint64_t(10) << 20);
  e.add("leaf origins compared", boolLeaves * 3 * sizeof(int32_t));
  vox::checkProcessMemory(e, "comparing " + o.a + " with " + o.b);
}

// Both files read at once: the two reads are independent and most of the time.
template <typename T, typename Read>
std::pair<T, T> readBoth(const DiffOptions& o, Read read) {
  auto second = std::async(std::launch::async, [&] { return read(o.b); });
  T first;
  try {
    first = read(o.a);
  } catch (...) {
    try {
      second.get();
    } catch (...) {
    }
    throw;
  }
  return {std::move(first), second.get()};
}

/// Level `level` of the pyramid at `path`, or the plain scene there as it is.
vox::Scene readLevel(const std::string& path, uint32_t level) {
  if (!vox::isPyramidVdb(path)) return vox::readSceneVdb(path);
  std::vector<vox::Scene> levels = vox::readPyramidVdb(path);
  if (level >= levels.size())
    throw vox::Error(vox::ErrorKind::Usage, path + " has levels 0.." + std::to_string(levels.size() - 1) +
                                                 "; --level " + std::to_string(level) + " is not one of them");
  return std::move(levels[level]);
}

}  // namespace

int diffSceneFiles(const DiffOptions& o) {
  const bool pyramid = vox::isPyramidVdb(o.a) || vox::isPyramidVdb(o.b);
  checkDiffMemory(o);
  if (!pyramid || o.level) {
    const uint32_t level = o.level.value_or(0);
    auto [a, b] = readBoth<vox::Scene>(o, [level](const std::string& p) { return readLevel(p, level); });
    const vox::SceneDiff d = vox::diffScenes(a, b, sceneOptions(o));
    if (o.json) {
      nlohmann::json j = sceneDiffJson(d, a.header(), b.header(), o);
      j["kind"] = "scene";
      j["a"] = o.a, j["b"] = o.b;
      if (o.level) j["level"] = *o.level;
      std::cout << vox::jsonText(j, 2) << "\n";
    } else {
      std::cout << (d.same() ? "same" : "DIFFERENT") << ": " << counted(d.voxelsCompared, "voxel", "voxels") << " compared, "
                << d.voxelsDiffering << " differ (" << (o.level ? "level " + std::to_string(*o.level) + ", " : "")
                << "scenes " << dimsText(a.header(), b.header()) << ")\n";
      std::cout << sceneDiffText(d, a.header(), b.header(), o, "  ");
    }
    return d.same() ? kExitOk : kExitCheckFailed;
  }
  auto [la, lb] =
      readBoth<std::vector<vox::Scene>>(o, [](const std::string& p) { return vox::readPyramidVdb(p); });
  bool same = la.size() == lb.size();
  auto metadata = [](const std::string& path) {  // "" for a plain scene
    const std::string text = vox::readPyramidMetadata(path);
    return vox::parseJsonDocument(text.empty() ? "null" : text, path + " vox:pyramid");
  };
  const vox::JsonDiff meta = vox::diffJson(metadata(o.a), metadata(o.b));
  same = same && meta.same();
  std::vector<vox::SceneDiff> diffs;
  uint64_t compared = 0, differing = 0;
  for (size_t i = 0; i < std::min(la.size(), lb.size()); ++i) {
    diffs.push_back(vox::diffScenes(la[i], lb[i], sceneOptions(o)));
    same = same && diffs.back().same();
    compared += diffs.back().voxelsCompared, differing += diffs.back().voxelsDiffering;
  }
  if (o.json) {
    nlohmann::json levels = nlohmann::json::array();
    for (size_t i = 0; i < diffs.size(); ++i) {
      nlohmann::json l = sceneDiffJson(diffs[i], la[i].header(), lb[i].header(), o);
      l["level"] = i;
      levels.push_back(l);
    }
    nlohmann::json j = {{"kind", "pyramid"},           {"a", o.a},
                        {"b", o.b},                    {"same", same},
                        {"levels_a", la.size()},       {"levels_b", lb.size()},
                        {"voxels_compared", compared}, {"voxels_differing", differing},
                        {"levels", levels},            {"metadata_same", meta.same()}};
    if (!meta.same() && !meta.differences.empty())
      j["metadata_first_difference"] = {{"pointer", meta.differences[0].pointer},
                                        {"a", meta.differences[0].a},
                                        {"b", meta.differences[0].b}};
    std::cout << vox::jsonText(j, 2) << "\n";
  } else {
    std::cout << (same ? "same" : "DIFFERENT") << ": pyramids of " << la.size() << " and " << lb.size()
              << " levels, " << counted(compared, "voxel", "voxels") << " compared, " << differing << " differ\n";
    if (la.size() != lb.size() && std::min(la.size(), lb.size()) == 1)
      std::cout << "  (a plain scene is a pyramid of one level; --level N compares one level with it)\n";
    if (!meta.same() && !meta.differences.empty())
      std::cout << "  pyramid metadata differs at " << pointerText(meta.differences[0].pointer) << ": "
                << meta.differences[0].a
                << " vs " << meta.differences[0].b << "\n";
    for (size_t i = 0; i < diffs.size(); ++i) {
      std::cout << "  level " << i << " (" << dimsText(la[i].header(), lb[i].header()) << "): "
                << (diffs[i].same() ? "same" : "DIFFERENT") << "\n";
      if (!diffs[i].same()) std::cout << sceneDiffText(diffs[i], la[i].header(), lb[i].header(), o, "    ");
    }
  }
  return same ? kExitOk : kExitCheckFailed;
}

}  // namespace voxcli
