# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Scenes as wide as block maps go (2^21 blocks) with a few blocks far apart:
# `vox export --format vox` costs their voxels, not the tiles of their box
# (little memory, a second), and `vox pack-chunks` refuses what no page-file
# reader accepts (an axis past 2^20) before the work, writing nothing.
foreach(group export_vox pack_chunks)
  add_test(NAME farscene.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/farscene_test.sh ${group} $<TARGET_FILE:vox>)
  set_tests_properties(farscene.${group} PROPERTIES TIMEOUT 600)
endforeach()
