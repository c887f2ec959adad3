# fixpoint_add_plugin(<name> <source>...)
#
# Builds a fixpoint plugin: a MODULE library named exactly <name>.so (no "lib" prefix),
# with hidden visibility and no GNU-unique symbols (each plugin keeps its own copies of
# inline statics when loaded with RTLD_LOCAL), linked against the SDK library only.
function(fixpoint_add_plugin name)
  if(NOT ARGN)
    message(FATAL_ERROR "fixpoint_add_plugin(${name}): no source files")
  endif()
  add_library(${name} MODULE ${ARGN})
  target_link_libraries(${name} PRIVATE fixpoint::sdk)
  set_target_properties(${name} PROPERTIES
    PREFIX ""
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  # No FMA contraction: a vectorised loop and its scalar tail round alike, so batch results
  # equal point-by-point results and images do not depend on how points are batched.
  target_compile_options(${name} PRIVATE -fno-gnu-unique -ffp-contract=off)
  target_link_options(${name} PRIVATE -Wl,--no-undefined)
  if(DEFINED FIXPOINT_PLUGIN_OUTPUT_DIR)
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${FIXPOINT_PLUGIN_OUTPUT_DIR})
  endif()
  set_property(GLOBAL APPEND PROPERTY FIXPOINT_PLUGIN_TARGETS ${name})
  if(DEFINED FIXPOINT_PLUGIN_INSTALL_DIR)
    set_target_properties(${name} PROPERTIES INSTALL_RPATH "$ORIGIN/../..")
    install(TARGETS ${name} LIBRARY DESTINATION ${FIXPOINT_PLUGIN_INSTALL_DIR})
  endif()
endfunction()
