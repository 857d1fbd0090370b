# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# `vox diff` (docs/diff.md): unit tests of the comparisons, end-to-end groups
# (tests/cli/diff_test.sh), image metrics against an independent numpy script
# (tests/diff/image_metrics.py) and the demo's golden files (tests/golden/diff/).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_diff.cpp)
foreach(group scenes images pages json render_reference kinds options metrics_numpy golden_demo)
  add_test(NAME diff.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/diff_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR})
  set_tests_properties(diff.${group} PROPERTIES TIMEOUT 600)
endforeach()
