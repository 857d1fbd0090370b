# Included by tests/CMakeLists.txt: CMAKE_CURRENT_SOURCE_DIR is tests/.
# OBJ and PLY polygons cut into triangles (formats/mesh/polygon_triangulation.h,
# docs/voxelize.md "Polygons"): convex ones keep the fan, concave ones are cut
# inside the polygon (areas, winding, voxels against explicit triangles).
target_sources(vox_unit_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test_polygon_triangulation.cpp)
