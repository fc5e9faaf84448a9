# Benchmarks (Google Benchmark); targets live here, never in timed unit tests.
find_package(benchmark QUIET)
file(GLOB MMNVS_BENCH_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/bench/*.cpp)
if(benchmark_FOUND)
  foreach(bench_source ${MMNVS_BENCH_SOURCES})
    get_filename_component(bench ${bench_source} NAME_WE)
    add_executable(${bench} ${bench_source})
    target_link_libraries(${bench} multimodal_nvs_core benchmark::benchmark)
    target_compile_definitions(${bench} PRIVATE
      MMNVS_DATA_DIR_DEFAULT="${MMNVS_DATA_DIR_DEFAULT}")
  endforeach()
endif()
