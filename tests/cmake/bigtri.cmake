# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The surface pass's tiles (docs/voxelize.md): large, coloured, textured and
# block-boundary triangles give the same scene at every thread count, and a
# wall cut along y keeps its exact area votes.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_surface_tiles.cpp)
