# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Texture images decoded while the mesh is baked (formats/mesh/deferred_textures.h,
# docs/gltf.md "Performance"): the bake takes texels only once they are decoded,
# the same bytes as decoding first at --threads 1 and 2, and an image that does
# not decode is still refused (exit 3, nothing written).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_deferred_textures.cpp)
add_test(NAME texoverlap.deferred_decode
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/texoverlap_test.sh $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR})
set_tests_properties(texoverlap.deferred_decode PROPERTIES TIMEOUT 300)
