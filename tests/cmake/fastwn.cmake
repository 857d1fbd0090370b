# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The hierarchical winding-number solid fill (docs/voxelize.md): block bounds
# against the brute-force oracle on multi-tile grids with many holes, and
# determinism at any thread count.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_fastwn.cpp)
