# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Corrupt .vdb files: the structure walk and CheckedVdbFile (unit), and every
# command that reads a .vdb on corrupted scenes, pyramids, level sets and fog
# volumes (end to end: exit 3, file and grid named, no output left).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_vdb_structure.cpp)
add_test(NAME vdbsafe.cli
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/vdb_corrupt_test.sh $<TARGET_FILE:vox>
                 ${CMAKE_CURRENT_SOURCE_DIR})
set_tests_properties(vdbsafe.cli PROPERTIES TIMEOUT 600)
