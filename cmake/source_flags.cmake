# mmnvs_source_flags(TARGET <target> OPTIONS <flag>... SOURCES <file>...): compile options for a
# named list of a target's source files. Parity and vectorisation depend on some of these flags, so
# a renamed or moved file must fail the configure instead of silently losing its flags.
function(mmnvs_source_flags)
  cmake_parse_arguments(ARG "" "TARGET" "OPTIONS;SOURCES" ${ARGN})
  get_target_property(target_sources ${ARG_TARGET} SOURCES)
  foreach(source ${ARG_SOURCES})
    set(path ${CMAKE_CURRENT_SOURCE_DIR}/${source})
    if(NOT EXISTS ${path})
      message(FATAL_ERROR "per-file flags ${ARG_OPTIONS}: ${source} does not exist (renamed?)")
    endif()
    if(NOT path IN_LIST target_sources)
      message(FATAL_ERROR "per-file flags ${ARG_OPTIONS}: ${source} is not a source of ${ARG_TARGET}")
    endif()
    set_property(SOURCE ${path} APPEND PROPERTY COMPILE_OPTIONS ${ARG_OPTIONS})
    # Compiled exactly as its flags say, without the target's precompiled headers
    # (precompiled_headers.cmake).
    set_property(SOURCE ${path} PROPERTY SKIP_PRECOMPILE_HEADERS ON)
  endforeach()
endfunction()
