#include <gtest/gtest.h>

#include "formats/core/file_kinds.h"

TEST(FileKinds, ByExtensionIgnoringCase) {
  using vox::FileKind;
  EXPECT_EQ(vox::fileKindOf("a/model.OBJ"), FileKind::Mesh);
  EXPECT_EQ(vox::fileKindOf("m.glb"), FileKind::Mesh);
  EXPECT_EQ(vox::fileKindOf("map.json"), FileKind::BlockMap);
  EXPECT_EQ(vox::fileKindOf("s.Vdb"), FileKind::Vdb);
  EXPECT_EQ(vox::fileKindOf("p.vpk"), FileKind::PageFile);
  EXPECT_EQ(vox::fileKindOf("shot.canonical.exr"), FileKind::Image);
  EXPECT_FALSE(vox::fileKindOf("notes.txt").has_value());
  EXPECT_FALSE(vox::fileKindOf("obj").has_value());
  EXPECT_TRUE(vox::hasExtension("X.VDB", ".vdb"));
  EXPECT_FALSE(vox::hasExtension("vdb", ".vdb"));
}

TEST(FileKinds, DescriptionsListEveryExtension) {
  EXPECT_EQ(vox::describe(vox::FileKind::Mesh), "a mesh (.obj .ply .stl .gltf .glb)");
  EXPECT_EQ(vox::describe(vox::FileKind::Image), "an image (atlas, bitmap or render) (.png .exr)");
  EXPECT_TRUE(vox::isDemoName("demo:hamlet"));
  EXPECT_FALSE(vox::isDemoName("hamlet.vdb"));
}
