# Layers 2 and 3: conversions between ROS messages and core types, the nodelets and their nodes.
file(GLOB MMNVS_ROS_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/ros/*.cpp)
if(MMNVS_ROS_SOURCES)
  add_library(multimodal_nvs_ros ${MMNVS_ROS_SOURCES})
  target_include_directories(multimodal_nvs_ros PUBLIC ${catkin_INCLUDE_DIRS})
  target_link_libraries(multimodal_nvs_ros PUBLIC multimodal_nvs_core ${catkin_LIBRARIES})
  add_dependencies(multimodal_nvs_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)
endif()
