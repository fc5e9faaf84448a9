# ROS-free command-line tools: every src/tools/<name>.cpp is a tool called <name>. Tools that need
# rosbag (and the ROS message conversions) list themselves in MMNVS_ROSBAG_TOOLS.
add_library(multimodal_nvs_cli STATIC src/tools/common/cli.cpp src/tools/common/depth_options.cpp)
target_include_directories(multimodal_nvs_cli PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/src/tools)
target_link_libraries(multimodal_nvs_cli PUBLIC multimodal_nvs_core)

set(MMNVS_ROSBAG_TOOLS vod_to_bag)
file(GLOB MMNVS_TOOL_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/tools/*.cpp)
foreach(tool_source ${MMNVS_TOOL_SOURCES})
  get_filename_component(tool ${tool_source} NAME_WE)
  add_executable(${tool} ${tool_source})
  target_link_libraries(${tool} multimodal_nvs_cli)
  if(tool IN_LIST MMNVS_ROSBAG_TOOLS)
    target_include_directories(${tool} PRIVATE ${catkin_INCLUDE_DIRS})
    target_link_libraries(${tool} multimodal_nvs_ros ${catkin_LIBRARIES})
  endif()
  install(TARGETS ${tool} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()
