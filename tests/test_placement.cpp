#include <gtest/gtest.h>

#include "libvox/mesh/placement.h"
#include "test_util.h"

using namespace vox;

TEST(Placement, ResolutionOnTheLongestAxis) {
  SceneHeader h;
  PlacementOptions o;
  o.resolution = 256;
  placeGrid({-1, 0, 2}, {3, 1, 2.5}, o, h);
  EXPECT_EQ(h.dims, (Dims{256, 64, 32}));
  EXPECT_DOUBLE_EQ(h.voxelSize, 4.0 / 256);
  EXPECT_EQ(h.origin, (std::array<double, 3>{-1, 0, 2}));
  // --pad 2: the layer the box's faces touch, then 2 empty ones, on every side.
  o.pad = 2;
  placeGrid({-1, 0, 2}, {3, 1, 2.5}, o, h);
  EXPECT_EQ(h.dims, (Dims{262, 70, 38}));
  EXPECT_DOUBLE_EQ(h.origin[0], -1 - 3 * 4.0 / 256);
}

TEST(Placement, FlatInputsResolutionOneAndBounds) {
  SceneHeader h;
  PlacementOptions o;
  o.resolution = 1;
  placeGrid({0, 0, 0}, {348, 404, 0}, o, h);  // woody.obj: z extent exactly 0
  EXPECT_EQ(h.dims, (Dims{1, 1, 1}));
  o.resolution = 4096;
  placeGrid({0, 0, 0}, {348, 404, 0}, o, h);
  EXPECT_EQ(h.dims.y, 4096u);
  EXPECT_EQ(h.dims.z, 1u) << "zero thickness gives one layer";
  o.bounds = std::array<double, 6>{0, 0, 0, 10, 10, 10};
  o.resolution = 10;
  placeGrid({-100, -100, -100}, {100, 100, 100}, o, h);
  EXPECT_EQ(h.dims, (Dims{10, 10, 10}));
  EXPECT_DOUBLE_EQ(h.voxelSize, 1.0);
}

TEST(Placement, Errors) {
  SceneHeader h;
  PlacementOptions o;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { placeGrid({0, 0, 0}, {1, 1, 1}, o, h); }, ErrorKind::Usage,
                                      {"a resolution or a voxel size"}));
  EXPECT_EQ(voxtest::settingOfError([&] { placeGrid({0, 0, 0}, {1, 1, 1}, o, h); }), Setting::VoxelSpacing);
  o.resolution = 8;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { placeGrid({1, 1, 1}, {1, 1, 1}, o, h); }, ErrorKind::BadInput,
                                      {"zero extent", "give a voxel size"}));
  EXPECT_EQ(voxtest::settingOfError([&] { placeGrid({1, 1, 1}, {1, 1, 1}, o, h); }), Setting::VoxelSize);
  o.resolution = 0;
  o.voxelSize = 1e-9;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { placeGrid({0, 0, 0}, {1, 1, 1}, o, h); }, ErrorKind::Usage,
                                      {"1000000000 voxels on an axis", "limit"}));
  EXPECT_EQ(voxtest::settingOfError([&] { placeGrid({0, 0, 0}, {1, 1, 1}, o, h); }), Setting::VoxelSpacing);
  o.voxelSize = 1e-300;  // past any integer: the count in powers of ten, not a wrapped-around 0
  EXPECT_TRUE(voxtest::throwsVoxError([&] { placeGrid({0, 0, 0}, {1, 1, 1}, o, h); }, ErrorKind::Usage,
                                      {"1e+300 voxels on an axis"}));
  // The padding alone too long: it is what the message names, not the voxel size.
  o.voxelSize = 0;
  o.resolution = 8;
  o.pad = 40000;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { placeGrid({0, 0, 0}, {1, 1, 1}, o, h); }, ErrorKind::Usage,
                                      {"80010 voxels", "80002 of them the padding", "lower --pad"}));
}
