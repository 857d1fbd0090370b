# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The light render module (vox-render.so, docs/startup.md): render-canonical
# without OpenVDB writes exactly what vox-cmds.so writes (matrix: scenes,
# page files, modes, cameras, threads, compared with cmp), takes the light
# path for scenes voxbake wrote and page files, and defers other files with
# the full module's messages (path). The leaves as a render source against
# OpenVDB's scene are unit tests in test_vdb_direct_read.cpp.
foreach(group matrix path)
  add_test(NAME lightrender.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/lightrender_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR}/..)
  set_tests_properties(lightrender.${group} PROPERTIES TIMEOUT 900)
endforeach()
