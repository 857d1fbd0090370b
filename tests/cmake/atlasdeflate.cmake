# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# build-atlas's parallel encoders (issue 14): sliced PNGs decode to the same
# texels as libpng's, PNG and EXR bytes independent of the thread count (unit),
# and every build-atlas output byte-identical at --threads 1, 2, 3 (end to end).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_atlas_deflate.cpp)
add_test(NAME atlasdeflate.threads
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/atlasdeflate_test.sh $<TARGET_FILE:vox>)
set_tests_properties(atlasdeflate.threads PROPERTIES TIMEOUT 600)
