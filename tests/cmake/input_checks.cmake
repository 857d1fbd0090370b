# Inputs that are not what they claim, and numbers at the edge of what a scene
# holds: messages, exit codes, no output (README "Exit codes").
# Every JSON document vox reads refuses duplicate keys (formats/core/json_input.h).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_json_input.cpp)
foreach(group numbers files unreadable outputs lists json_keys)
  add_test(NAME input_checks.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/input_checks_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR}/cli)
  set_tests_properties(input_checks.${group} PROPERTIES TIMEOUT 300)
endforeach()
