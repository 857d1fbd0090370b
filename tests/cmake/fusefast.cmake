# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# `vox fuse --free voted` (docs/fuse.md, "Free space"): the tracked walk that
# jumps empty bricks against the full walk (tests/test_fusefast.cpp).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_fusefast.cpp)
# End to end: --free voted and --free all carve the same scene; vox info names the free grid.
add_test(NAME fusefast.scopes
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/fusefast_test.sh scopes $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR})
set_tests_properties(fusefast.scopes PROPERTIES TIMEOUT 600)
