# Layer 1: the ROS-free core (Eigen + OpenCV only).
file(GLOB MMNVS_CORE_SOURCES CONFIGURE_DEPENDS
  ${CMAKE_CURRENT_SOURCE_DIR}/src/core/*.cpp ${CMAKE_CURRENT_SOURCE_DIR}/src/core/*/*.cpp)
add_library(multimodal_nvs_core ${MMNVS_CORE_SOURCES})
# The per-pixel GP prediction needs no bit-level parity, so it may use fused multiply-add.
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/src/core/gp_prediction.cpp
  PROPERTIES COMPILE_OPTIONS -ffp-contract=fast)
target_include_directories(multimodal_nvs_core PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
target_include_directories(multimodal_nvs_core SYSTEM PUBLIC
  ${EIGEN3_INCLUDE_DIRS} ${OpenCV_INCLUDE_DIRS})
target_link_libraries(multimodal_nvs_core PUBLIC ${OpenCV_LIBS} Threads::Threads)
set_target_properties(multimodal_nvs_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
install(TARGETS multimodal_nvs_core
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
