# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The memory guard (docs/reliability.md "Memory"): sizes, limits and the mesh
# footprint against real block counts (unit), refusals, estimates against
# measured peaks, build-atlas layer by layer and allocation failures (end to end).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_memory_budget.cpp)
foreach(group refusals atlas estimates accuracy oom)
  add_test(NAME memguard.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/memory_guard_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_SOURCE_DIR}/../shared/data)
  set_tests_properties(memguard.${group} PROPERTIES TIMEOUT 900)
endforeach()
