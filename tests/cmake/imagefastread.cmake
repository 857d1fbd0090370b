# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The image readers' fast paths (libdeflate PNG decoding, EXR scanline chunks)
# read every file as libpng and OpenEXR themselves read it (unit).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_image_fast_read.cpp)
