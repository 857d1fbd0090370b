# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Merging the page files of a region bake's parts (vox pack-chunks --merge).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_pagemerge.cpp)
add_test(NAME pagemerge.cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/pagemerge_test.sh $<TARGET_FILE:vox>)
set_tests_properties(pagemerge.cli PROPERTIES TIMEOUT 900)
