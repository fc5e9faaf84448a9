# mmnvs_precompile_headers(<target> [TESTS]): parses the third-party and standard headers that most
# of the target's files include (Eigen, OpenCV; gtest for TESTS) once per target instead of once
# per file. Why: CI builds the package three times on 2 cores (Release, ASan + UBSan, TSan), and a
# file that includes nothing but Eigen, OpenCV and gtest took 3.4 s to compile under the ASan flags
# (0.6 s with the standard headers alone). Measured under those flags, 2 jobs: the core library's
# files 208 s -> 115 s + 7.5 s for the header, test_core's and test_tools' 233 s -> 180 s + 14 s.
# Files with flags of their own (mmnvs_source_flags) are compiled without it, exactly as before: a
# header precompiled under the target's flags would be rejected for some of them and could parse
# differently for others. The others' code is the same either way: the header is parsed with the
# same flags as the file, and optimisation happens per file after parsing.
# -DMMNVS_PRECOMPILED_HEADERS=OFF builds without them.
option(MMNVS_PRECOMPILED_HEADERS "Precompile the common third-party headers per target" ON)

set(MMNVS_COMMON_HEADERS
  <Eigen/Core> <Eigen/Geometry> <opencv2/core.hpp> <opencv2/imgproc.hpp>
  <algorithm> <array> <cmath> <cstdint> <cstring> <functional> <limits> <memory> <string> <vector>)
set(MMNVS_TEST_HEADERS <gtest/gtest.h> <filesystem> <fstream> <random> <sstream>)

function(mmnvs_precompile_headers target)
  cmake_parse_arguments(ARG "TESTS" "" "" ${ARGN})
  if(NOT MMNVS_PRECOMPILED_HEADERS)
    return()
  endif()
  set(headers ${MMNVS_COMMON_HEADERS})
  if(ARG_TESTS)
    list(APPEND headers ${MMNVS_TEST_HEADERS})
  endif()
  target_precompile_headers(${target} PRIVATE ${headers})
endfunction()
