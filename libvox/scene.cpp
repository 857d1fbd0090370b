#include "libvox/scene.h"

#include <algorithm>
#include <mutex>

#include "libvox/error.h"
#include "libvox/scene_grids.h"

namespace vox {

void ensureOpenVdbInitialized() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

namespace {

openvdb::Coord toVdb(Coord3 c) { return openvdb::Coord(c.u, c.v, c.w); }
Coord3 fromVdb(const openvdb::Coord& c) { return {c.x(), c.y(), c.z()}; }

std::unique_ptr<SceneGrids> makeEmptyGrids() {
  ensureOpenVdbInitialized();
  auto g = std::make_unique<SceneGrids>();
  g->occupancy = openvdb::BoolGrid::create(false);
  g->occupancy->setName("occupancy");
  return g;
}

openvdb::Int32Grid::Ptr& voteGrid(SceneGrids& g, uint8_t classId) {
  auto at = std::lower_bound(g.votes.begin(), g.votes.end(), classId,
                             [](const ClassGrid& c, uint8_t id) { return c.classId < id; });
  if (at == g.votes.end() || at->classId != classId) {
    ClassGrid cg{classId, openvdb::Int32Grid::create(0)};
    at = g.votes.insert(at, std::move(cg));
  }
  return at->grid;
}

uint32_t saturatingAdd(uint32_t a, uint32_t b) {
  uint64_t s = uint64_t(a) + b;
  return s > kMaxVotesPerClass ? kMaxVotesPerClass : uint32_t(s);
}

}  // namespace

// ---------------------------------------------------------------- Scene

Scene::Scene() : grids_(makeEmptyGrids()) {}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;
Scene::~Scene() = default;

bool Scene::hasColor() const { return grids_->color != nullptr; }

uint64_t Scene::occupiedCount() const { return grids_->occupancy->activeVoxelCount(); }

std::vector<uint8_t> Scene::classesPresent() const {
  std::vector<uint8_t> ids;
  for (const ClassGrid& c : grids_->votes) ids.push_back(c.classId);
  return ids;
}

std::optional<VoxelView> Scene::voxel(Coord3 c, std::vector<ClassVotes>& storage) const {
  const Dims& d = header_.dims;
  if (c.u < 0 || c.v < 0 || c.w < 0 || uint32_t(c.u) >= d.x || uint32_t(c.v) >= d.y ||
      uint32_t(c.w) >= d.z)
    return std::nullopt;
  const openvdb::Coord xyz = toVdb(c);
  bool surface = false;
  if (!grids_->occupancy->tree().probeValue(xyz, surface)) return std::nullopt;
  storage.clear();
  for (const ClassGrid& cg : grids_->votes) {
    int32_t n = 0;
    if (cg.grid->tree().probeValue(xyz, n)) storage.push_back({cg.classId, uint32_t(n)});
  }
  VoxelView view;
  view.at = c;
  view.surface = surface;
  view.votes = storage;
  if (grids_->color) {
    openvdb::Vec3s rgb;
    if (grids_->color->tree().probeValue(xyz, rgb)) view.color = RgbLinear{rgb[0], rgb[1], rgb[2]};
  }
  return view;
}

void Scene::forEachVoxel(const std::function<void(const VoxelView&)>& fn) const {
  std::vector<openvdb::Int32Grid::ConstAccessor> accessors;
  for (const ClassGrid& cg : grids_->votes) accessors.push_back(cg.grid->getConstAccessor());
  std::optional<openvdb::Vec3SGrid::ConstAccessor> colorAcc;
  if (grids_->color) colorAcc.emplace(grids_->color->getConstAccessor());
  std::vector<ClassVotes> storage;
  storage.reserve(grids_->votes.size());
  for (auto leaf = grids_->occupancy->tree().cbeginLeaf(); leaf; ++leaf) {
    for (auto it = leaf->cbeginValueOn(); it; ++it) {
      const openvdb::Coord xyz = it.getCoord();
      storage.clear();
      for (size_t i = 0; i < accessors.size(); ++i) {
        int32_t n = 0;
        if (accessors[i].probeValue(xyz, n)) storage.push_back({grids_->votes[i].classId, uint32_t(n)});
      }
      VoxelView view;
      view.at = fromVdb(xyz);
      view.surface = *it;
      view.votes = storage;
      if (colorAcc) {
        openvdb::Vec3s rgb;
        if (colorAcc->probeValue(xyz, rgb)) view.color = RgbLinear{rgb[0], rgb[1], rgb[2]};
      }
      fn(view);
    }
  }
}

SceneStats Scene::stats() const {
  SceneStats s;
  std::vector<SceneStats::PerClass> per(grids_->votes.size());
  for (size_t i = 0; i < per.size(); ++i) per[i].classId = grids_->votes[i].classId;
  forEachVoxel([&](const VoxelView& v) {
    ++s.occupied;
    if (v.surface) ++s.surface;
    if (v.color) ++s.colored;
    if (s.occupied == 1) {
      s.bounds.min = s.bounds.max = v.at;
    } else {
      s.bounds.min = {std::min(s.bounds.min.u, v.at.u), std::min(s.bounds.min.v, v.at.v),
                      std::min(s.bounds.min.w, v.at.w)};
      s.bounds.max = {std::max(s.bounds.max.u, v.at.u), std::max(s.bounds.max.v, v.at.v),
                      std::max(s.bounds.max.w, v.at.w)};
    }
    uint8_t best = 0;
    uint32_t bestVotes = 0;
    for (const ClassVotes& cv : v.votes) {
      auto& p = *std::find_if(per.begin(), per.end(),
                              [&](const SceneStats::PerClass& q) { return q.classId == cv.classId; });
      ++p.voxelsWithVotes;
      p.votes += cv.votes;
      if (cv.votes > bestVotes) {  // votes are sorted by id, so ties keep the lowest id
        best = cv.classId;
        bestVotes = cv.votes;
      }
    }
    if (best)
      for (auto& p : per)
        if (p.classId == best) ++p.modeVoxels;
  });
  s.perClass = std::move(per);
  s.memoryBytes = grids_->occupancy->memUsage();
  for (const ClassGrid& cg : grids_->votes) s.memoryBytes += cg.grid->memUsage();
  if (grids_->color) s.memoryBytes += grids_->color->memUsage();
  return s;
}

// ---------------------------------------------------------------- SceneBuilder

struct SceneBuilder::Cache {
  explicit Cache(SceneGrids& g) : occupancy(g.occupancy->tree()) {}
  openvdb::BoolGrid::Accessor occupancy;
  std::vector<std::pair<uint8_t, openvdb::Int32Grid::Accessor>> votes;  // small, linear search
};

SceneBuilder::SceneBuilder(SceneHeader header)
    : header_(std::move(header)), grids_(makeEmptyGrids()), cache_(std::make_unique<Cache>(*grids_)) {}
SceneBuilder::SceneBuilder(SceneBuilder&&) noexcept = default;
SceneBuilder::~SceneBuilder() = default;

void SceneBuilder::addVotes(Coord3 c, uint8_t classId, uint32_t votes, bool surface) {
  if (votes == 0) return;
  const openvdb::Coord xyz = toVdb(c);
  bool wasSurface = false;
  const bool wasOn = cache_->occupancy.probeValue(xyz, wasSurface);
  if (!wasOn || (surface && !wasSurface)) cache_->occupancy.setValueOn(xyz, wasSurface || surface);
  openvdb::Int32Grid::Accessor* acc = nullptr;
  for (auto& [id, a] : cache_->votes)
    if (id == classId) acc = &a;
  if (!acc) {
    openvdb::Int32Grid::Ptr& grid = voteGrid(*grids_, classId);
    cache_->votes.emplace_back(classId, grid->getAccessor());
    acc = &cache_->votes.back().second;
  }
  int32_t old = 0;
  acc->probeValue(xyz, old);
  acc->setValueOn(xyz, int32_t(saturatingAdd(uint32_t(old), votes)));
}

void SceneBuilder::setColor(Coord3 c, RgbLinear color) {
  if (!grids_->color) grids_->color = openvdb::Vec3SGrid::create(openvdb::Vec3s(0, 0, 0));
  grids_->color->tree().setValueOn(toVdb(c), openvdb::Vec3s(color.r, color.g, color.b));
}

void SceneBuilder::merge(SceneBuilder&& other) {
  for (auto it = other.grids_->occupancy->cbeginValueOn(); it; ++it) {
    // Tiles are never created by addVotes, so only voxel values occur here.
    bool was = false;
    const bool on = cache_->occupancy.probeValue(it.getCoord(), was);
    if (!on || (*it && !was)) cache_->occupancy.setValueOn(it.getCoord(), was || *it);
  }
  for (ClassGrid& cg : other.grids_->votes) {
    openvdb::Int32Grid::Ptr& mine = voteGrid(*grids_, cg.classId);
    auto acc = mine->getAccessor();
    for (auto it = cg.grid->cbeginValueOn(); it; ++it) {
      int32_t old = 0;
      acc.probeValue(it.getCoord(), old);
      acc.setValueOn(it.getCoord(), int32_t(saturatingAdd(uint32_t(old), uint32_t(*it))));
    }
  }
  if (other.grids_->color) {
    for (auto it = other.grids_->color->cbeginValueOn(); it; ++it) {
      openvdb::Vec3s rgb = *it;
      setColor(fromVdb(it.getCoord()), RgbLinear{rgb[0], rgb[1], rgb[2]});
    }
  }
  // Accessors cached in this builder may point at grids whose leaves changed.
  cache_ = std::make_unique<Cache>(*grids_);
  other.grids_ = makeEmptyGrids();
  other.cache_ = std::make_unique<Cache>(*other.grids_);
}

Scene SceneBuilder::build() && {
  const Dims& d = header_.dims;
  if (d.x == 0 || d.y == 0 || d.z == 0)
    throw Error(ErrorKind::Internal, "scene dims must be >= 1 on every axis, got " + toString(d));
  cache_.reset();
  const openvdb::CoordBBox domain(openvdb::Coord(0, 0, 0),
                                  openvdb::Coord(int32_t(d.x - 1), int32_t(d.y - 1), int32_t(d.z - 1)));
  const openvdb::CoordBBox active = grids_->occupancy->evalActiveVoxelBoundingBox();
  if (!grids_->occupancy->tree().empty() && !domain.isInside(active))
    throw Error(ErrorKind::Internal, "a voxel lies outside the scene domain " + toString(d));
  for (const ClassGrid& cg : grids_->votes)
    if (!header_.classes.find(cg.classId))
      throw Error(ErrorKind::Internal,
                  "class id " + std::to_string(cg.classId) + " has votes but is not in the class table");
  for (ClassGrid& cg : grids_->votes) {
    cg.grid->setName("votes." + std::to_string(cg.classId));
  }
  if (grids_->color) grids_->color->setName("color");
  Scene scene;
  scene.header_ = std::move(header_);
  scene.grids_ = std::move(grids_);
  return scene;
}

// ---------------------------------------------------------------- compare

namespace {
std::string headerDifference(const SceneHeader& a, const SceneHeader& b, bool ignoreSources) {
  if (!(a.dims == b.dims)) return "dims " + toString(a.dims) + " vs " + toString(b.dims);
  if (a.voxelSize != b.voxelSize) return "voxel size differs";
  if (a.origin != b.origin) return "origin differs";
  if (!(a.classes == b.classes)) return "class table differs";
  if (!ignoreSources && a.sources != b.sources) return "sources differ";
  if (a.mipLevel != b.mipLevel) return "mip level differs";
  if (a.blockWorld != b.blockWorld) return "block-world placement differs";
  return {};
}

std::string describe(const std::optional<VoxelView>& v) {
  if (!v) return "empty";
  std::string s = v->surface ? "surface" : "interior";
  s += " votes{";
  for (size_t i = 0; i < v->votes.size(); ++i)
    s += (i ? "," : "") + std::to_string(v->votes[i].classId) + ":" + std::to_string(v->votes[i].votes);
  s += "}";
  if (v->color)
    s += " color(" + std::to_string(v->color->r) + "," + std::to_string(v->color->g) + "," +
         std::to_string(v->color->b) + ")";
  return s;
}

bool sameVoxel(const std::optional<VoxelView>& a, const std::optional<VoxelView>& b) {
  if (a.has_value() != b.has_value()) return false;
  if (!a) return true;
  return a->surface == b->surface && a->color == b->color &&
         std::equal(a->votes.begin(), a->votes.end(), b->votes.begin(), b->votes.end());
}
}  // namespace

SceneDifference compareScenes(const Scene& a, const Scene& b, bool ignoreSources) {
  SceneDifference diff;
  diff.headerNote = headerDifference(a.header(), b.header(), ignoreSources);
  diff.headerDiffers = !diff.headerNote.empty();
  // Visit the union of both topologies: every voxel of a, then voxels of b not in a.
  std::vector<ClassVotes> sb;
  auto note = [&](Coord3 c, const std::optional<VoxelView>& va, const std::optional<VoxelView>& vb) {
    ++diff.voxelsDiffering;
    auto key = [](Coord3 p) { return std::tuple(p.w, p.v, p.u); };
    if (!diff.firstDifference || key(c) < key(*diff.firstDifference)) {
      diff.firstDifference = c;
      diff.firstNote = describe(va) + " vs " + describe(vb);
    }
  };
  a.forEachVoxel([&](const VoxelView& va) {
    ++diff.voxelsCompared;
    std::vector<ClassVotes> copy(va.votes.begin(), va.votes.end());
    VoxelView ca = va;
    ca.votes = copy;
    auto vb = b.voxel(va.at, sb);
    if (!sameVoxel(ca, vb)) note(va.at, ca, vb);
  });
  b.forEachVoxel([&](const VoxelView& vb) {
    if (!a.grids().occupancy->tree().isValueOn(toVdb(vb.at))) {
      ++diff.voxelsCompared;
      note(vb.at, std::nullopt, vb);
    }
  });
  return diff;
}

}  // namespace vox
