# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# `vox mip` without OpenVDB (vox-pack.so, docs/startup.md): the pyramid and
# --split files the light module writes are vox-cmds.so's, byte for byte but
# for the UUID (matrix: scenes, occupancy rules, levels, threads), the light
# path is taken for scenes voxbake wrote, and everything else is deferred
# with the full module's messages (path).
foreach(group matrix path)
  add_test(NAME lightmip.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/lightmip_test.sh ${group} $<TARGET_FILE:vox>)
  set_tests_properties(lightmip.${group} PROPERTIES TIMEOUT 900)
endforeach()
# Levels reduced on blocks against reduceScene (saturated sums, odd dims,
# partial colour), and the plain form of the leaves.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_mip_blocks.cpp)
