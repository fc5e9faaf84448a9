# Tests of the conditioning renderer's ROS layer and of the render_conditioning tool. Included from
# tests.cmake when testing is enabled (after ros_tests.cmake, which finds rostest and roslaunch).
find_package(rostest REQUIRED)
find_package(roslaunch REQUIRED)

# Conversions and the Config <-> settings mapping: plain gtest, no master.
catkin_add_gtest(test_renderer_conversions test/ros/test_renderer_conversions.cpp)
target_link_libraries(test_renderer_conversions multimodal_nvs_ros ${GTEST_MAIN_LIBRARIES})

# The render_conditioning tool end to end, as a process (its inputs are written by the test).
catkin_add_gtest(test_render_conditioning_tool test/ros/test_render_conditioning_tool.cpp)
target_link_libraries(test_render_conditioning_tool multimodal_nvs_core ${OpenCV_LIBS} ${GTEST_MAIN_LIBRARIES})
target_compile_definitions(test_render_conditioning_tool PRIVATE
  MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
add_dependencies(test_render_conditioning_tool render_conditioning)

# The nodelet in both trajectory modes (gtest-in-rostest), loaded into a manager and as the
# standalone node, through launch/conditioning_renderer.launch.
set(MMNVS_RENDERER_ROSTEST_DEPENDENCIES multimodal_nvs_nodelets conditioning_renderer_node)
add_dependencies(tests ${MMNVS_RENDERER_ROSTEST_DEPENDENCIES})
add_rostest_gtest(test_renderer test/ros/renderer.test test/ros/test_renderer.cpp)
target_include_directories(test_renderer SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(test_renderer multimodal_nvs_core ${catkin_LIBRARIES} ${OpenCV_LIBS})
add_dependencies(test_renderer ${MMNVS_RENDERER_ROSTEST_DEPENDENCIES})
add_rostest(test/ros/renderer.test ARGS mode:=standalone
  DEPENDENCIES test_renderer ${MMNVS_RENDERER_ROSTEST_DEPENDENCIES})

roslaunch_add_file_check(launch/conditioning_renderer.launch USE_TEST_DEPENDENCIES)

# Latency benchmark of a running renderer in tf mode (not a test; built on request):
#   make bench_renderer, then see the header of test/ros/bench_renderer.cpp.
add_executable(bench_renderer EXCLUDE_FROM_ALL test/ros/bench_renderer.cpp)
target_include_directories(bench_renderer SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(bench_renderer ${catkin_LIBRARIES} ${OpenCV_LIBS})
