# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Fuzzing (docs/fuzzing.md). The libFuzzer targets of tests/fuzz/ are built by
# scripts/fuzz_all.sh with clang; here they are compiled into the unit tests
# with VOX_FUZZ_REPLAY, which replay every committed regression and seed
# through them (FuzzRegressions.*), and fuzz.smoke runs each target briefly
# when clang++ is installed (else it prints SKIP and passes).
set(VOX_FUZZ_REPLAY_TARGETS gltf blockmap classes camera touched classtable rendermeta atlasmeta png exr)
foreach(target ${VOX_FUZZ_REPLAY_TARGETS})
  target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/fuzz_${target}.cpp)
  set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/fuzz/fuzz_${target}.cpp PROPERTIES COMPILE_DEFINITIONS VOX_FUZZ_REPLAY)
endforeach()
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_fuzz_regressions.cpp)

add_test(NAME fuzz.smoke COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/smoke.sh ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR})
set_tests_properties(fuzz.smoke PROPERTIES TIMEOUT 1500)
