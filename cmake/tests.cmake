# Core unit tests: one gtest binary from test/core/*.cpp, no ROS master needed.
file(GLOB MMNVS_CORE_TEST_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/test/core/*.cpp)
catkin_add_gtest(test_core ${MMNVS_CORE_TEST_SOURCES} WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(test_core multimodal_nvs_core multimodal_nvs_cli ${GTEST_MAIN_LIBRARIES})
target_include_directories(test_core PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/test)
target_compile_definitions(test_core PRIVATE
  MMNVS_DATA_DIR_DEFAULT="${MMNVS_DATA_DIR_DEFAULT}"
  MMNVS_TOOL_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")

# ROS-side tests (rostest, gtest-in-rostest) register themselves in ros_tests.cmake.
include(cmake/ros_tests.cmake OPTIONAL)
include(cmake/renderer_ros_tests.cmake OPTIONAL)
include(cmake/bag_tests.cmake OPTIONAL)
include(cmake/pipeline_tests.cmake OPTIONAL)
