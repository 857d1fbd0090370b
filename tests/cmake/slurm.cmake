# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# Region bakes on real engines (docs/scale.md, "Running on Slurm and make"):
# a one-node Slurm cluster on localhost (tests/slurm/slurm_cluster.sh; needs
# root, slurm-wlm and munge, else skipped with exit 77), scripts/bake-slurm.sh
# on it, and scripts/bake.mk under make -j2. RUN_SERIAL: the cluster's jobs
# and make -j2 use both cores.
foreach(group cluster bake)
  add_test(NAME slurm.${group}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/slurm/bake_test.sh ${group}
                   $<TARGET_FILE:vox> ${CMAKE_SOURCE_DIR})
  set_tests_properties(slurm.${group} PROPERTIES TIMEOUT 900 SKIP_RETURN_CODE 77 RUN_SERIAL TRUE)
endforeach()
add_test(NAME make.bake
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/slurm/bake_test.sh make
                 $<TARGET_FILE:vox> ${CMAKE_SOURCE_DIR})
set_tests_properties(make.bake PROPERTIES TIMEOUT 900 RUN_SERIAL TRUE)
