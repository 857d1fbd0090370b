# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# `vox fuse` (docs/fuse.md): unit tests against render-canonical's caster
# (tests/test_fuse.cpp) and end-to-end groups (tests/cli/fuse_test.sh).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_fuse.cpp)
foreach(group roundtrip carving refine bad_input extremes png_depth image8k)
  add_test(NAME fuse.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/fuse_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR})
  set_tests_properties(fuse.${group} PROPERTIES TIMEOUT 600)
endforeach()
# The noise study (not a test: scripts/study_fuse_noise.sh runs it and writes docs/fuse-noise.md).
add_executable(vox_fuse_noise_study ${CMAKE_CURRENT_SOURCE_DIR}/fuse/noise_study.cpp)
target_link_libraries(vox_fuse_noise_study PRIVATE libvox)
