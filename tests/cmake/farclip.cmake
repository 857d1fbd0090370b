# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Triangles reaching more than 2^20 voxels from the grid (docs/voxelize.md,
# "Range"): a surface fill clips them to the grid (unit tests against the exact
# oracle and a clip by hand), a city-like crop through the CLI, and the solid
# fill's refusal.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_voxelize_far.cpp)
add_test(NAME farclip.city COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/farclip_test.sh $<TARGET_FILE:vox>)
set_tests_properties(farclip.city PROPERTIES TIMEOUT 600)
