# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# glTF extensions (docs/gltf.md): Draco, quantization, texture transforms,
# instancing and required extensions, each against the same model without it.
add_test(NAME gltfext.extensions
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/gltfext_test.sh $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR})
set_tests_properties(gltfext.extensions PROPERTIES TIMEOUT 600)
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_gltf_ext.cpp)
# The meshopt tests compress with the same library's encoder.
target_link_libraries(vox_unit_tests PRIVATE meshoptimizer::meshoptimizer)
# The texture decoder both mesh readers use; its tests write JPEG and WebP files.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_texture_image.cpp)
target_link_libraries(vox_unit_tests PRIVATE JPEG::JPEG ${WEBP_LIBRARY})
# The Draco index test encodes its file with Draco's own encoder (the same
# archive the reader links).
target_link_libraries(vox_unit_tests PRIVATE voxdraco)
