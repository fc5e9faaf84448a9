# Round trip of the vod_to_bag converter: a plain gtest (no ROS master) that writes a tiny
# synthetic scene with the core, runs the vod_to_bag tool on it and reads the bag back with rosbag.
# Included from tests.cmake when testing is enabled.
catkin_add_gtest(test_vod_to_bag test/ros/test_vod_to_bag.cpp
  WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR})
if(TARGET test_vod_to_bag)
  target_include_directories(test_vod_to_bag SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(test_vod_to_bag multimodal_nvs_core ${catkin_LIBRARIES}
    ${GTEST_MAIN_LIBRARIES})
  target_compile_definitions(test_vod_to_bag PRIVATE
    MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
  add_dependencies(test_vod_to_bag vod_to_bag)
endif()
