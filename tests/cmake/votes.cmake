# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Vote blocks and block colours kept compactly (libvox/mesh/voxel_blocks.h
# ClassBlock, VoxelBlock::colors) against a plain value per voxel: random adds,
# saturation, overwrites, merges, interior runs.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_class_block.cpp
                                      ${CMAKE_CURRENT_SOURCE_DIR}/test_block_colors.cpp)
