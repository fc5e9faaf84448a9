# mmnvs_local_template_symbols(<target>): links a shared library or a test binary with
# local_template_symbols.map, which keeps Eigen's functions and std::vector's instantiations over
# Eigen types or Eigen's aligned allocator out of its dynamic symbol table (the map says why).
# test_exported_symbols.cpp checks it.
set(MMNVS_LOCAL_TEMPLATE_SYMBOLS_MAP ${CMAKE_CURRENT_LIST_DIR}/local_template_symbols.map)
function(mmnvs_local_template_symbols target)
  target_link_options(${target} PRIVATE
    "LINKER:--version-script=${MMNVS_LOCAL_TEMPLATE_SYMBOLS_MAP}")
  set_property(TARGET ${target} APPEND PROPERTY LINK_DEPENDS ${MMNVS_LOCAL_TEMPLATE_SYMBOLS_MAP})
endfunction()
