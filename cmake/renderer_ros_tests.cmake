# Tests of the conditioning renderer's ROS layer: conversions (plain gtest) and the nodelet (rostest).
# Included from tests.cmake (after ros_tests.cmake, which finds rostest and roslaunch).
find_package(rostest REQUIRED)
find_package(roslaunch REQUIRED)

# Conversions and the Config <-> settings mapping: plain gtest, no master.
catkin_add_gtest(test_renderer_conversions test/ros/test_renderer_conversions.cpp)
target_link_libraries(test_renderer_conversions multimodal_nvs_ros ${GTEST_MAIN_LIBRARIES})
# The keyframe policy and keyframe, the preset burst and the per-frame steps: plain gtests, no
# master.
catkin_add_gtest(test_renderer_keyframe test/ros/test_renderer_keyframe.cpp)
target_link_libraries(test_renderer_keyframe multimodal_nvs_ros ${GTEST_MAIN_LIBRARIES})
catkin_add_gtest(test_preset_burst test/ros/test_preset_burst.cpp)
target_link_libraries(test_preset_burst multimodal_nvs_ros ${GTEST_MAIN_LIBRARIES})
# The per-frame steps (keyframe, live view, burst) with stand-ins for tf and the publishers.
catkin_add_gtest(test_renderer_session test/ros/test_renderer_session.cpp)
target_link_libraries(test_renderer_session multimodal_nvs_ros ${GTEST_MAIN_LIBRARIES})
catkin_add_gtest(test_renderer_recorded_export test/ros/test_renderer_recorded_export.cpp)
target_link_libraries(test_renderer_recorded_export multimodal_nvs_ros ${GTEST_MAIN_LIBRARIES})
catkin_add_gtest(test_renderer_view_frames test/ros/test_renderer_view_frames.cpp)
target_link_libraries(test_renderer_view_frames multimodal_nvs_ros ${GTEST_MAIN_LIBRARIES})

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
