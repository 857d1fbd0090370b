# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# --fill solid by the generalised winding number (docs/voxelize.md): unit tests
# against the brute-force oracle, and real meshes end to end (--check's interior IoU).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_winding.cpp)
add_test(NAME winding.real_meshes
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/winding_test.sh $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR})
set_tests_properties(winding.real_meshes PROPERTIES TIMEOUT 900)
