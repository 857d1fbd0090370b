# The sanitizer defaults of a VOX_SANITIZE build (tests/sanitizers/default_options.cpp)
# in the unit tests too, so a plain ctest there is as strict as scripts/test-sanitizers.sh.
if(VOX_SANITIZE)
  target_sources(vox_unit_tests PRIVATE ${VOX_SANITIZER_DEFAULTS})
  # On that file only (the root CMakeLists.txt says why).
  set_source_files_properties(${VOX_SANITIZER_DEFAULTS} PROPERTIES COMPILE_DEFINITIONS "${VOX_SANITIZER_DEFINE}")
endif()

# The sorting of a sanitizer run's failures that decides which tests
# scripts/test-sanitizers.sh runs once more (LeakSanitizer's own tracer crash).
find_package(Python3 REQUIRED COMPONENTS Interpreter)
add_test(NAME sanitizers.classify
         COMMAND ${Python3_EXECUTABLE} ${CMAKE_SOURCE_DIR}/scripts/sanitizer_failures.py --self-test)

# The sanitizer defaults survive a dynamic TLS block where GCC 12's runtime
# misreads its bounds (google/sanitizers#1409; tests/sanitizers/dynamic_tls_test.sh).
if(VOX_SANITIZE)
  add_library(vox_dynamic_tls_module MODULE ${CMAKE_CURRENT_SOURCE_DIR}/sanitizers/dynamic_tls_module.cpp)
  add_executable(vox_dynamic_tls_probe ${CMAKE_CURRENT_SOURCE_DIR}/sanitizers/dynamic_tls_probe.cpp
                                       ${VOX_SANITIZER_DEFAULTS})
  target_link_libraries(vox_dynamic_tls_probe PRIVATE ${CMAKE_DL_LIBS})
  add_test(NAME sanitizers.dynamic_tls
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/sanitizers/dynamic_tls_test.sh
                   $<TARGET_FILE:vox_dynamic_tls_probe> $<TARGET_FILE:vox_dynamic_tls_module>)
  set_tests_properties(sanitizers.dynamic_tls PROPERTIES TIMEOUT 120)
endif()
