# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Interrupted runs (signals, SIGKILL then a rerun, ulimit -f): exit codes,
# messages, no temporary left, existing outputs untouched, no directory the
# run made left behind.
foreach(group voxelize derived sigkill file_size_limit many_outputs commit_window rollback atlas_directories)
  add_test(NAME signals.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/signal_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_CURRENT_SOURCE_DIR}/cli)
  set_tests_properties(signals.${group} PROPERTIES TIMEOUT 600)
endforeach()
