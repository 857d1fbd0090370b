# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The inline rounding that snaps vertices to the lattice and grid coordinates
# in the memory estimate, against libm's std::round and std::llround.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_round_half_away.cpp)
