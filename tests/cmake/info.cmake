# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# `vox info` for every artefact, build-atlas --preview, class tables of mesh
# bakes, mip --split stems and empty references.
target_sources(vox_unit_tests PRIVATE
               ${CMAKE_CURRENT_SOURCE_DIR}/test_info_text.cpp
               ${CMAKE_CURRENT_SOURCE_DIR}/test_info_preview.cpp
               ${CMAKE_CURRENT_SOURCE_DIR}/test_info_classes.cpp
               ${CMAKE_CURRENT_SOURCE_DIR}/test_display_width.cpp
               # The text helpers have no dependencies: tested here directly.
               ${CMAKE_SOURCE_DIR}/tools/cmds/info_text.cpp)
foreach(group scene artefacts json preview classes mip atlas_inputs wide)
  add_test(NAME info.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/info_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR}/cli)
  set_tests_properties(info.${group} PROPERTIES TIMEOUT 600)
endforeach()
