# ROS-side tests. Included from tests.cmake when testing is enabled.
find_package(rostest REQUIRED)
find_package(roslaunch REQUIRED)

# Conversions, the Config <-> params mapping and the nodelet's input policies: plain gtest, no
# master.
catkin_add_gtest(test_ros_conversions test/ros/test_ros_conversions.cpp
  test/ros/test_depth_frame.cpp test/ros/test_frame_synchronizer.cpp)
target_link_libraries(test_ros_conversions multimodal_nvs_ros)

# Synthetic-scene input for the rate tests (a test helper, not installed).
add_executable(scene_publisher EXCLUDE_FROM_ALL test/ros/scene_publisher.cpp)
target_include_directories(scene_publisher SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(scene_publisher multimodal_nvs_ros ${catkin_LIBRARIES})
add_dependencies(tests scene_publisher)

# The rostests start the node through launch/depth_completion.launch: both the nodelet (in a
# manager) and the standalone node. They need the plugin library and the node built.
set(MMNVS_ROSTEST_DEPENDENCIES multimodal_nvs_nodelets depth_completion_node scene_publisher)
add_dependencies(tests multimodal_nvs_nodelets depth_completion_node)

foreach(scenario depth_scene depth_bad_input depth_adversarial)
  add_rostest_gtest(test_${scenario} test/ros/${scenario}.test test/ros/test_${scenario}.cpp)
  target_include_directories(test_${scenario} SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(test_${scenario} multimodal_nvs_ros ${catkin_LIBRARIES})
  add_dependencies(test_${scenario} ${PROJECT_NAME}_generate_messages_cpp
    ${MMNVS_ROSTEST_DEPENDENCIES})
  add_rostest(test/ros/${scenario}.test ARGS mode:=standalone
    DEPENDENCIES test_${scenario} ${MMNVS_ROSTEST_DEPENDENCIES})
endforeach()
target_link_libraries(test_depth_scene ${OpenCV_LIBS})
add_rostest(test/ros/depth_scene.test ARGS compressed:=true
  DEPENDENCIES test_depth_scene ${MMNVS_ROSTEST_DEPENDENCIES})

add_rostest(test/ros/depth_hz.test DEPENDENCIES ${MMNVS_ROSTEST_DEPENDENCIES})
add_rostest(test/ros/depth_hz.test ARGS mode:=standalone DEPENDENCIES ${MMNVS_ROSTEST_DEPENDENCIES})

roslaunch_add_file_check(launch USE_TEST_DEPENDENCIES)
