# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# `vox fuse` speed work (issue 17, docs/bench-fuse.md): the flat vote table
# against an ordered-map oracle.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_fuse_speed.cpp)
