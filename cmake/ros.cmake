# Layers 2 and 3: conversions between ROS messages and core types, the nodelets and their nodes.
# Generated headers (messages, dynamic_reconfigure configs) live in the devel space.
set(MMNVS_GENERATED_INCLUDE_DIR ${CATKIN_DEVEL_PREFIX}/${CATKIN_GLOBAL_INCLUDE_DESTINATION})

file(GLOB MMNVS_ROS_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/ros/*.cpp)
add_library(multimodal_nvs_ros ${MMNVS_ROS_SOURCES})
target_include_directories(multimodal_nvs_ros PUBLIC ${MMNVS_GENERATED_INCLUDE_DIR})
target_include_directories(multimodal_nvs_ros SYSTEM PUBLIC ${catkin_INCLUDE_DIRS})
target_link_libraries(multimodal_nvs_ros PUBLIC multimodal_nvs_core ${catkin_LIBRARIES})
add_dependencies(multimodal_nvs_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)
mmnvs_local_template_symbols(multimodal_nvs_ros)

# Every nodelet of the package goes into one plugin library; its name is the path in
# nodelet_plugins.xml (lib/libmultimodal_nvs_nodelets).
file(GLOB MMNVS_NODELET_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/nodelets/*.cpp)
add_library(multimodal_nvs_nodelets ${MMNVS_NODELET_SOURCES})
target_link_libraries(multimodal_nvs_nodelets PUBLIC multimodal_nvs_ros)
mmnvs_local_template_symbols(multimodal_nvs_nodelets)
add_dependencies(multimodal_nvs_nodelets
  ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)

# Standalone nodes: src/nodes/<name>.cpp loads its nodelet class through pluginlib.
file(GLOB MMNVS_NODE_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/nodes/*.cpp)
foreach(node_source ${MMNVS_NODE_SOURCES})
  get_filename_component(node ${node_source} NAME_WE)
  add_executable(${node} ${node_source})
  target_include_directories(${node} SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
  # The core only for retainFreedMemory (the process-wide allocator setting a node may make).
  target_link_libraries(${node} multimodal_nvs_core ${catkin_LIBRARIES})
  # The node finds the plugin at run time; building it alone must still build the plugin.
  add_dependencies(${node} multimodal_nvs_nodelets)
  install(TARGETS ${node} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()

install(TARGETS multimodal_nvs_ros multimodal_nvs_nodelets
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(FILES nodelet_plugins.xml pcl_ros_filters.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
# What the launch files find through $(find multimodal_nvs) in the install space as in the source
# tree: the launch files, parameter files and rviz layout; the player's wrapper script goes with
# the executables (roslaunch resolves $(find multimodal_nvs)/scripts/X to lib/multimodal_nvs/X
# there, and to the source tree's scripts/X in the devel space).
install(DIRECTORY cfg config launch rviz DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(PROGRAMS scripts/run_then_linger.sh DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
