# Layer 1: the ROS-free core (Eigen, OpenCV; nlohmann-json and yaml-cpp for the file formats, CGAL
# for Delaunay triangulation): every .cpp under src/core/, one folder a topic.
file(GLOB_RECURSE MMNVS_CORE_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/core/*.cpp)
add_library(multimodal_nvs_core ${MMNVS_CORE_SOURCES})
target_include_directories(multimodal_nvs_core PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
target_include_directories(multimodal_nvs_core SYSTEM PUBLIC
  ${EIGEN3_INCLUDE_DIRS} ${OpenCV_INCLUDE_DIRS})
target_link_libraries(multimodal_nvs_core PUBLIC ${OpenCV_LIBS} Threads::Threads nlohmann_json::nlohmann_json)
# CGAL's exact fallback of its filtered predicates calls GMP (the link would otherwise rely on
# another library pulling libgmp in).
find_library(MMNVS_GMP_LIBRARY gmp REQUIRED)
target_link_libraries(multimodal_nvs_core PRIVATE yaml-cpp ${MMNVS_GMP_LIBRARY})
# libdeflate (Debian libdeflate-dev) compresses and checksums the PNGs the exports write: several
# times faster than zlib through OpenCV's libpng path.
find_path(MMNVS_DEFLATE_INCLUDE_DIR libdeflate.h REQUIRED)
find_library(MMNVS_DEFLATE_LIBRARY deflate REQUIRED)
target_include_directories(multimodal_nvs_core SYSTEM PRIVATE ${MMNVS_DEFLATE_INCLUDE_DIR})
target_link_libraries(multimodal_nvs_core PRIVATE ${MMNVS_DEFLATE_LIBRARY})
set_target_properties(multimodal_nvs_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
mmnvs_local_template_symbols(multimodal_nvs_core)
mmnvs_precompile_headers(multimodal_nvs_core)

# PCD files go through PCL's reader. Only pcl_common and pcl_io, by file: the pcl_io target's
# interface would add VTK, OpenNI and libusb to every program that links the core. One file includes
# PCL's headers (they are slow to compile), as system headers (PCL's own warnings are not ours).
find_package(PCL 1.10 REQUIRED COMPONENTS common io)
set(MMNVS_PCL_SOURCES src/core/io/pcd_reader.cpp)
mmnvs_source_flags(TARGET multimodal_nvs_core OPTIONS -isystem ${PCL_COMMON_INCLUDE_DIR}
  SOURCES ${MMNVS_PCL_SOURCES})
target_link_libraries(multimodal_nvs_core PRIVATE ${PCL_IO_LIBRARY} ${PCL_COMMON_LIBRARY})

# Files that need flags of their own (the package default is -ffp-contract=off, for parity).
# The per-pixel GP prediction and the bilateral filter need no bit-level parity with a reference,
# so they may use fused multiply-add.
set(MMNVS_FUSED_MULTIPLY_ADD_SOURCES src/core/depth/gp/gp_prediction.cpp
  src/core/common/bilateral_filter.cpp)
# ground_gp's full-image pass chooses between ground, surface and far depth per pixel; GCC turns
# those choices into vector blends only if floating-point exceptions need not be preserved (nothing
# reads the FP status flags; results are unchanged). The bilateral filter's column loop (NaN rules,
# a branch-free exponential), ipbasic's output pass and kernel regression's moments (two divisions
# by a weight sum that may be 0 where the result is then not selected) vectorise only under the
# same flag.
set(MMNVS_NO_TRAPPING_MATH_SOURCES src/core/depth/models/ground_gp_model.cpp
  src/core/common/bilateral_filter.cpp src/core/depth/models/ipbasic_model.cpp
  src/core/depth/models/kernel_model.cpp)
mmnvs_source_flags(TARGET multimodal_nvs_core OPTIONS -ffp-contract=fast
  SOURCES ${MMNVS_FUSED_MULTIPLY_ADD_SOURCES})
mmnvs_source_flags(TARGET multimodal_nvs_core OPTIONS -fno-trapping-math
  SOURCES ${MMNVS_NO_TRAPPING_MATH_SOURCES})
# The exact distance transform's last step, sqrt of each row's squared distances, vectorises only
# if sqrt need not set errno (its arguments are never negative; results are unchanged).
set(MMNVS_NO_MATH_ERRNO_SOURCES src/core/common/distance_transform.cpp)
mmnvs_source_flags(TARGET multimodal_nvs_core OPTIONS -fno-math-errno
  SOURCES ${MMNVS_NO_MATH_ERRNO_SOURCES})
# CGAL's filtered predicates (interval arithmetic) need -frounding-math. Only the file that uses
# CGAL gets it: linking the CGAL::CGAL target would put it on every core file (slower code, and
# the parity-critical arithmetic compiled differently).
set(MMNVS_CGAL_SOURCES src/core/depth/angular_triangulation.cpp)
mmnvs_source_flags(TARGET multimodal_nvs_core OPTIONS -frounding-math SOURCES ${MMNVS_CGAL_SOURCES})

install(TARGETS multimodal_nvs_core
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
