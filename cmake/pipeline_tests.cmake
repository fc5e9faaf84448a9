# The whole pipeline (launch/pipeline.launch: depth completion + conditioning renderer in one
# manager) on a short synthetic bag, and checks of the pipeline and demo launch files. Included
# from tests.cmake when testing is enabled (after ros_tests.cmake, which finds rostest and
# roslaunch). The test writes its bag with make_synthetic_scene and vod_to_bag at run time.
find_package(rostest REQUIRED)
find_package(roslaunch REQUIRED)

set(MMNVS_PIPELINE_TEST_DEPENDENCIES multimodal_nvs_nodelets make_synthetic_scene vod_to_bag)
add_dependencies(tests ${MMNVS_PIPELINE_TEST_DEPENDENCIES})

add_rostest_gtest(test_pipeline test/ros/pipeline.test test/ros/test_pipeline.cpp)
target_include_directories(test_pipeline SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(test_pipeline ${catkin_LIBRARIES})
target_compile_definitions(test_pipeline PRIVATE
  MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
add_dependencies(test_pipeline ${PROJECT_NAME}_generate_messages_cpp
  ${MMNVS_PIPELINE_TEST_DEPENDENCIES})
add_rostest(test/ros/pipeline.test ARGS sensor:=lidar
  DEPENDENCIES test_pipeline ${MMNVS_PIPELINE_TEST_DEPENDENCIES})
# LiDAR through pcl_ros's CropBox and VoxelGrid nodelets (rostest multimodal_nvs pipeline.test
# sensor:=lidar pcl:=true) is not part of make test yet: on the loaded machine only 2 of 4 frames
# got through the longer chain, which fails the every-frame checks.

# The launch files with their defaults, and with other arguments through a launch file that
# includes them (roslaunch-check passes no launch arguments). demo.launch's bag defaults to
# ./demo_output/scene.bag (what `make demo` writes); the check does not need the file.
roslaunch_add_file_check(launch/pipeline.launch USE_TEST_DEPENDENCIES)
roslaunch_add_file_check(launch/demo.launch USE_TEST_DEPENDENCIES)
roslaunch_add_file_check(test/ros/pipeline_launch_variants.launch USE_TEST_DEPENDENCIES)

# The paper's experiment on the VoD 08350-08365 bag (real data; skipped without it unless CI=true):
# 16 live conditioning frames in tf mode and a recorded-trajectory export equal to
# render_conditioning's.
add_rostest_gtest(test_renderer_vod test/ros/renderer_vod.test test/ros/test_renderer_vod.cpp)
target_include_directories(test_renderer_vod SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(test_renderer_vod multimodal_nvs_core ${catkin_LIBRARIES})
target_compile_definitions(test_renderer_vod PRIVATE
  MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}"
  MMNVS_DATA_DIR_DEFAULT="${MMNVS_DATA_DIR_DEFAULT}")
add_dependencies(test_renderer_vod ${PROJECT_NAME}_generate_messages_cpp
  ${MMNVS_PIPELINE_TEST_DEPENDENCIES} render_conditioning)

# rviz with rviz/multimodal_nvs.rviz under Xvfb, the demo pipeline playing a short synthetic bag:
# the depth and standard-deviation panels of a screenshot must show their colour images
# (scripts/rviz_screenshot.sh; at most RVIZ_WAIT 90 s of polling per attempt). rviz runs on Mesa's
# softpipe there: with the default llvmpipe it crashed at start-up inside the LLVM shader JIT on a
# loaded machine (the script's comment has the numbers); a crash is retried once.
catkin_add_gtest(test_rviz_screenshot test/ros/test_rviz_screenshot.cpp)
target_include_directories(test_rviz_screenshot PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test)
target_link_libraries(test_rviz_screenshot ${GTEST_MAIN_LIBRARIES})
target_compile_definitions(test_rviz_screenshot PRIVATE
  MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}"
  MMNVS_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
add_dependencies(test_rviz_screenshot ${MMNVS_PIPELINE_TEST_DEPENDENCIES})
