# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# demo:city (docs/city.md): determinism, the crop contract region bakes rely on
# (a box equals the whole city cropped to it), features, surface flags against
# a brute-force neighbour walk (tests/test_demo_city.cpp); the CLI's options
# and errors end to end (tests/cli/city_test.sh).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_demo_city.cpp)
add_test(NAME city.cli COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/city_test.sh $<TARGET_FILE:vox>)
set_tests_properties(city.cli PROPERTIES TIMEOUT 600)
# The box benchmark (not a test: scripts/bench_city.sh runs it, docs/city.md records it).
add_executable(vox_bench_city_boxes ${CMAKE_CURRENT_SOURCE_DIR}/city/bench_city_boxes.cpp)
target_link_libraries(vox_bench_city_boxes PRIVATE libvox)
