# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Seeing a scene (render-canonical): the color mode, named views and orbits
# framed on the occupied box, camera files, the voxel-walk check reference,
# monotone progress; end to end in cli/render_view_test.sh.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_render_views.cpp)
foreach(group color views check progress)
  add_test(NAME render_view.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/render_view_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR}/..)
  set_tests_properties(render_view.${group} PROPERTIES TIMEOUT 600)
endforeach()
