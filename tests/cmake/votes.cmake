# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Vote blocks kept compactly (libvox/mesh/voxel_blocks.h ClassBlock) against a
# plain count per voxel: random adds, saturation, merges, interior runs.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_class_block.cpp)
