# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# floor and ceil without libm (libvox/core/floor_int.h) against std::floor and
# std::ceil, the functions they replace in the surface pass and the fuse walk.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_floor_int.cpp)
