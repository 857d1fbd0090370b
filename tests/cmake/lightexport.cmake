# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# The light export module (vox-export.so, docs/startup.md): `vox export` of
# scenes voxbake wrote and page files to glTF, PLY and MagicaVoxel without
# OpenVDB writes exactly what vox-cmds.so writes (matrix: scenes, page file
# levels, formats, options, regions, threads, compared with cmp), takes the
# light path for them, and defers .vdb volumes, pyramids and other files with
# the full module's messages (path). The leaves' class volume against
# OpenVDB's is a unit test in test_export_files.cpp.
foreach(group matrix path)
  add_test(NAME lightexport.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/lightexport_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR}/..)
  set_tests_properties(lightexport.${group} PROPERTIES TIMEOUT 900)
endforeach()
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_scene_leaves_class_volume.cpp)
