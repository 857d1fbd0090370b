# The sanitizer defaults of a VOX_SANITIZE build (tests/sanitizers/default_options.cpp)
# in the unit tests too, so a plain ctest there is as strict as scripts/test-sanitizers.sh.
if(VOX_SANITIZE)
  target_sources(vox_unit_tests PRIVATE ${VOX_SANITIZER_DEFAULTS})
  target_compile_definitions(vox_unit_tests PRIVATE ${VOX_SANITIZER_DEFINE})
endif()
