# The surface pass's candidate voxels (issue 14, votes at 0.7x): the voxels
# found from the exact pieces equal the exact test's, slivers included.
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_voxelize_candidates.cpp)
