# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The scene writer's Blosc frames (formats/scene/blosc_lz4_frame.h): the same
# bytes as Blosc's own blosc_compress_ctx, input by input.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_blosc_lz4_frame.cpp)
