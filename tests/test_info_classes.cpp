// Class tables of mesh bakes: materials that share a name share a class, the
// default material is a visible grey, and classes without a voxel are left out
// (libvox/mesh/class_mapping.h, libvox/mesh/class_compaction.h).
#include <gtest/gtest.h>

#include "libvox/mesh/class_compaction.h"
#include "libvox/mesh/class_mapping.h"
#include "libvox/mesh/voxel_blocks.h"

using namespace vox;

namespace {
Mesh sharedNames() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles.assign(6, {0, 1, 2});
  m.materials = {{"Wall", {1, 0, 0, 1}},   {"Roof", {0, 0, 1, 1}}, {"Wall", {0, 1, 0, 1}},
                 {"", {1, 1, 1, 1}, -1, 0}, {"", {1, 1, 1, 1}, -1, 0}, {"", {0, 0, 0, 1}}};
  m.triangleMaterial = {0, 1, 2, 3, 4, 5};
  m.parts = {{"node", "mesh"}};
  m.trianglePart.assign(6, 0);
  return m;
}
}  // namespace

TEST(InfoClasses, MaterialsThatShareANameShareAClass) {
  const Mesh m = sharedNames();
  const ClassMapping c = classPerMaterial(m, "m.glb");
  ASSERT_EQ(c.table.size(), 4u) << "Wall, Roof, default, material 5: no 'Wall #2'";
  EXPECT_EQ(c.table.find(1)->name, "Wall");
  EXPECT_EQ(c.table.find(1)->color, (Rgb8{255, 0, 0})) << "the first material of a name gives the colour";
  EXPECT_EQ(c.table.find(2)->name, "Roof");
  EXPECT_EQ(c.table.find(3)->name, "default");
  EXPECT_EQ(c.table.find(3)->color, (Rgb8{150, 150, 150})) << "no material: grey #969696, not white";
  EXPECT_EQ(c.table.find(4)->name, "material 5") << "an unnamed material with a colour keeps its own class";
  EXPECT_EQ(c.table.find(4)->color, (Rgb8{0, 0, 0}));
  EXPECT_EQ(c.materialClass, (std::vector<uint8_t>{1, 2, 1, 3, 3, 4}));
  EXPECT_EQ(assignClasses(m, c), (std::vector<uint8_t>{1, 2, 1, 3, 3, 4}));
}

TEST(InfoClasses, APlainMeshIsOneGreyDefaultClass) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  m.materials = {{"", {1, 1, 1, 1}, -1, 0}};  // what the STL/PLY/OBJ readers give
  m.triangleMaterial = {0};
  const ClassMapping c = classPerMaterial(m, "m.stl");
  ASSERT_EQ(c.table.size(), 1u);
  EXPECT_EQ(c.table.find(1)->name, kDefaultClassName);
  EXPECT_EQ(c.table.find(1)->color, kDefaultClassColor);
}

TEST(InfoClasses, UnusedClassesAreLeftOutInOrder) {
  ClassTable t;
  for (int i = 1; i <= 4; ++i) t.add({uint8_t(i), "c" + std::to_string(i), {uint8_t(i), 0, 0}, std::nullopt});
  std::vector<uint8_t> tri = {4, 2, 4};
  ClassTable dense = t;
  const ClassRemap r = compactClassTable(dense, classesOfTriangles(tri), ClassIds::Dense);
  ASSERT_EQ(dense.size(), 2u);
  EXPECT_EQ(dense.find(1)->name, "c2") << "order kept: c2 before c4";
  EXPECT_EQ(dense.find(2)->name, "c4");
  EXPECT_EQ(dense.find(2)->color, (Rgb8{4, 0, 0})) << "a class keeps its colour when renumbered";
  EXPECT_EQ(r[2], 1);
  EXPECT_EQ(r[4], 2);
  EXPECT_EQ(r[1], 0);
  EXPECT_EQ(r[3], 0);
  remapTriangleClasses(tri, r);
  EXPECT_EQ(tri, (std::vector<uint8_t>{2, 1, 2}));

  ClassTable kept = t;
  const ClassRemap k = compactClassTable(kept, classesOfTriangles({4, 2}), ClassIds::Keep);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_TRUE(kept.find(2) && kept.find(4)) << "ids a class rules file chose stay";
  EXPECT_EQ(k[4], 4);
  EXPECT_EQ(k[1], 0);
}

TEST(InfoClasses, BlocksAreRenumberedWithTheTable) {
  VoxelBlocks blocks;
  blocks.addVotes({1, 2, 3}, 5, 10, true);
  blocks.addVotes({1, 2, 3}, 2, 7, true);
  blocks.addRun({9, 0, 0}, 4, 5, 65536, false);
  ClassTable t;
  for (int i = 1; i <= 5; ++i) t.add({uint8_t(i), "c" + std::to_string(i), {}, std::nullopt});
  const std::array<bool, 256> used = classesWithVotes(blocks, t);
  for (int i = 0; i < 256; ++i) EXPECT_EQ(used[size_t(i)], i == 2 || i == 5) << i;
  const ClassRemap r = compactClassTable(t, used, ClassIds::Dense);
  remapBlockClasses(blocks, r);
  std::vector<uint8_t> ids;
  uint8_t runClass = 0;
  for (const VoxelBlock* b : blocks.sortedBlocks()) {
    for (const auto& cb : b->classes) ids.push_back(cb->classId);
    if (b->hasRuns()) runClass = b->runClass;
  }
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<uint8_t>{1, 2})) << "class 2 -> 1, class 5 -> 2";
  EXPECT_EQ(runClass, 2) << "run votes follow their class";
  const std::array<bool, 256> after = classesWithVotes(blocks, t);
  EXPECT_TRUE(after[1] && after[2] && !after[5]);
}
