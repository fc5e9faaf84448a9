# Benchmarks (not tests: speed targets live here, never in timed unit tests). `make bench` runs
# bench/run_benchmarks.sh, which prints the median of every case.
#   bench/*.cpp      Google Benchmark binaries over the core (one executable per file)
#   bench/ros_conversions/*.cpp  the same over the ROS message conversions (no master)
#   bench/ros/*.cpp  harnesses that drive a running node (need a master; see each file's header)
find_package(benchmark QUIET)
file(GLOB MMNVS_BENCH_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/bench/*.cpp)
if(benchmark_FOUND)
  foreach(bench_source ${MMNVS_BENCH_SOURCES})
    get_filename_component(bench ${bench_source} NAME_WE)
    add_executable(${bench} ${bench_source})
    target_link_libraries(${bench} multimodal_nvs_core benchmark::benchmark yaml-cpp)
    target_compile_definitions(${bench} PRIVATE
      MMNVS_DATA_DIR_DEFAULT="${MMNVS_DATA_DIR_DEFAULT}"
      MMNVS_SOURCE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
  endforeach()
  # The depth nodelet's message conversions (ROS message types, no master).
  add_executable(bench_ros_conversions bench/ros_conversions/bench_ros_conversions.cpp)
  target_link_libraries(bench_ros_conversions multimodal_nvs_ros benchmark::benchmark)
endif()

# Node latency harness: bench/ros/bench_depth_node.sh starts the node and drives it with this.
add_executable(bench_depth_node bench/ros/bench_depth_node.cpp)
target_link_libraries(bench_depth_node multimodal_nvs_ros)
add_dependencies(bench_depth_node ${PROJECT_NAME}_generate_messages_cpp)

# Latency of the running renderer in tf mode: bench/ros/bench_renderer.sh drives it.
add_executable(bench_renderer bench/ros/bench_renderer.cpp)
target_include_directories(bench_renderer SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(bench_renderer ${catkin_LIBRARIES} ${OpenCV_LIBS})
