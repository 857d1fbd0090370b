# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The one-pass scene reader (formats/vdb/vdb_scene_direct_read.h) against
# OpenVDB's reader: scenes made in the test (unit), and scenes made by
# `vox voxelize` from meshes, block maps, demos and regions, compared by the
# unit test binary (end to end).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_vdb_direct_read.cpp)
add_test(NAME directread.cli
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/direct_read_test.sh $<TARGET_FILE:vox>
                 $<TARGET_FILE:vox_unit_tests> ${CMAKE_CURRENT_SOURCE_DIR})
set_tests_properties(directread.cli PROPERTIES TIMEOUT 600)
