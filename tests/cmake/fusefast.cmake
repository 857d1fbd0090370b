# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# `vox fuse --free voted` (docs/fuse.md, "Free space"): the tracked walk that
# jumps empty bricks against the full walk (tests/test_fusefast.cpp).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_fusefast.cpp)
