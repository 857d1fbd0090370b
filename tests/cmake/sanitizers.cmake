# The sanitizer defaults of a VOX_SANITIZE build (tests/sanitizers/default_options.cpp)
# in the unit tests too, so a plain ctest there is as strict as scripts/test-sanitizers.sh.
if(VOX_SANITIZE)
  target_sources(vox_unit_tests PRIVATE ${VOX_SANITIZER_DEFAULTS})
  target_compile_definitions(vox_unit_tests PRIVATE ${VOX_SANITIZER_DEFINE})
endif()

# The sorting of a sanitizer run's failures that decides which tests
# scripts/test-sanitizers.sh runs once more (LeakSanitizer's own tracer crash).
find_package(Python3 REQUIRED COMPONENTS Interpreter)
add_test(NAME sanitizers.classify
         COMMAND ${Python3_EXECUTABLE} ${CMAKE_SOURCE_DIR}/scripts/sanitizer_failures.py --self-test)
