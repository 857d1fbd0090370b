# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The number parser of the text mesh readers (formats/core/text_numbers.h)
# against std::from_chars.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_text_numbers.cpp)
