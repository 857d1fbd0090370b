# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# `vox fuse` speed work (issue 17, docs/bench-fuse.md): the flat vote table
# against an ordered-map oracle.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_fuse_speed.cpp)
# End to end: the memory guard, the second pass's reuse of decoded views, and
# parallel decoding failing in view order (tests/cli/fusespeed_test.sh).
foreach(group memory reuse loaderror)
  add_test(NAME fusespeed.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/fusespeed_test.sh ${group} $<TARGET_FILE:vox>)
  set_tests_properties(fusespeed.${group} PROPERTIES TIMEOUT 600)
endforeach()
