# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Region bakes (docs/scale.md "Regions", "Merging scenes"): every part equals
# the whole bake cropped to its tile, merges equal the whole bake (unit), and
# vox merge writes the single-process bake's bytes (end to end).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_region_bake.cpp)
add_test(NAME regionbake.cli
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/regions_test.sh $<TARGET_FILE:vox>)
set_tests_properties(regionbake.cli PROPERTIES TIMEOUT 900)
