# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Pixel tiles sharing one march through empty space (libvox/render/ray_bundle.h):
# the certified empty stretch against the brute force, rays started there
# against rays started at 0, and whole views against per-pixel casts.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_fastcast.cpp)
