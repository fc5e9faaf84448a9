# Tests mirror the source tree. Included from CMakeLists.txt when testing is enabled.
#   test/core/**   one gtest binary over the core, no ROS master
#   test/tools/    the command-line tools run as processes on inputs the tests write
#   test/ros/      conversions (plain gtest) and the nodelets (rostest), in the cmake/*_tests.cmake
# mmnvs_add_gtest(NAME SOURCES...): a gtest over the core and the CLI helpers, run from the
# repository root, with the real-data folder and the tools' folder compiled in (test_data.hpp,
# tool_runner.hpp).
function(mmnvs_add_gtest name)
  catkin_add_gtest(${name} ${ARGN} WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(${name} multimodal_nvs_core multimodal_nvs_cli ${GTEST_MAIN_LIBRARIES})
  # test_core writes PCD fixtures with PCL, whose calls would otherwise bind to the test's copies.
  mmnvs_local_template_symbols(${name})
  target_include_directories(${name} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test)
  mmnvs_precompile_headers(${name} TESTS)
  target_compile_definitions(${name} PRIVATE
    MMNVS_DATA_DIR_DEFAULT="${MMNVS_DATA_DIR_DEFAULT}"
    MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
endfunction()

file(GLOB_RECURSE MMNVS_CORE_TEST_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/test/core/*.cpp)
mmnvs_add_gtest(test_core ${MMNVS_CORE_TEST_SOURCES})
# The PCD reader's test writes its fixtures with PCL's own writer.
mmnvs_source_flags(TARGET test_core OPTIONS -isystem ${PCL_COMMON_INCLUDE_DIR}
  SOURCES test/core/io/test_pcd_reader.cpp)
target_link_libraries(test_core ${PCL_IO_LIBRARY} ${PCL_COMMON_LIBRARY})
# test_synthetic_scene runs make_synthetic_scene as a process.
add_dependencies(test_core make_synthetic_scene)

# The ROS-free tools end to end. vod_to_bag's test reads its bag back with rosbag, so it is a binary
# of its own (the sanitizer build runs test_tools without linking ROS).
mmnvs_add_gtest(test_tools test/tools/test_complete_depth_tool.cpp test/tools/test_evaluate_tool.cpp
  test/tools/test_render_conditioning_tool.cpp
  test/tools/test_tool_command_lines.cpp test/tools/test_camera_and_layout_tools.cpp
  test/tools/test_analysis_scripts.cpp test/tools/test_compare_builds.cpp)
add_dependencies(test_tools complete_depth evaluate_depth render_conditioning make_synthetic_scene)

catkin_add_gtest(test_vod_to_bag test/tools/test_vod_to_bag.cpp
  WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR})
target_include_directories(test_vod_to_bag PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test)
target_include_directories(test_vod_to_bag SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(test_vod_to_bag multimodal_nvs_core ${catkin_LIBRARIES} ${GTEST_MAIN_LIBRARIES})
target_compile_definitions(test_vod_to_bag PRIVATE
  MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
add_dependencies(test_vod_to_bag vod_to_bag make_synthetic_scene)

# The tools and nodes through rosrun, as README starts them (needs the sourced devel space, which
# scripts/run_tests.sh provides). Its own binary: the sanitizer build runs test_tools without ROS.
catkin_add_gtest(test_rosrun test/tools/test_rosrun.cpp WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR})
target_include_directories(test_rosrun PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test)
target_link_libraries(test_rosrun ${GTEST_MAIN_LIBRARIES})
target_compile_definitions(test_rosrun PRIVATE
  MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
add_dependencies(test_rosrun complete_depth vod_to_bag depth_completion_node)

# ROS-side tests: conversions (plain gtest) and the nodelets (rostest, gtest-in-rostest).
include(cmake/ros_tests.cmake)
include(cmake/renderer_ros_tests.cmake)
include(cmake/pipeline_tests.cmake)
