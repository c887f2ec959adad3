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
  # The folder of the plugin's first source on the include path: Highway's foreach_target
  # re-includes the source by the name in HWY_TARGET_INCLUDE (fixpoint/simd-inl.hpp).
  list(GET ARGN 0 first_source)
  get_filename_component(source_dir ${first_source} ABSOLUTE)
  get_filename_component(source_dir ${source_dir} DIRECTORY)
  target_include_directories(${name} PRIVATE ${source_dir})
  set_target_properties(${name} PROPERTIES
    PREFIX ""
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  # No FMA contraction: a vectorised loop and its scalar tail round alike, so batch results
  # equal point-by-point results and images do not depend on how points are batched.
  target_compile_options(${name} PRIVATE -ffp-contract=off)
  # Floating-point operations raise no traps the code cares about (it never unmasks them), so
  # the compiler may compute both arms of a select and keep one: loops with selects then
  # vectorise on every instruction set, not only on those with masked operations (AVX-512).
  # The values are IEEE's either way: no reassociation, no contraction.
  target_compile_options(${name} PRIVATE -fno-trapping-math)
  # Nor errno from the math functions: std::sqrt then stays one (vectorisable) instruction,
  # with the same correctly rounded result.
  target_compile_options(${name} PRIVATE -fno-math-errno)
  # Loops the compiler vectorises inside a kernel compiled for a 512-bit target (Highway's
  # per-target functions, fixpoint/simd-inl.hpp's per-point loops) get full-width vectors: GCC
  # prefers 256-bit ones by default. Here, not only in fixpoint's own tree, so that a plugin
  # built against the installed SDK gets the built-in plugins' code (bench/external.sh). Only
  # x86 compilers know the flag.
  include(CheckCXXCompilerFlag)
  check_cxx_compiler_flag(-mprefer-vector-width=512 FIXPOINT_PLUGIN_HAS_PREFER_512)
  if(FIXPOINT_PLUGIN_HAS_PREFER_512)
    target_compile_options(${name} PRIVATE -mprefer-vector-width=512)
  endif()
  # GCC only: clang does not know the flag, and never emits GNU-unique symbols anyway.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${name} PRIVATE -fno-gnu-unique)
  endif()
  # A plugin names no symbol that the SDK does not define. Not in a clang sanitizer build:
  # clang links the sanitizer runtime (and libFuzzer's coverage hooks) into executables
  # only, so a shared library leaves those symbols undefined until it is loaded.
  if(NOT (FIXPOINT_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "Clang"))
    target_link_options(${name} PRIVATE -Wl,--no-undefined)
  endif()
  if(DEFINED FIXPOINT_PLUGIN_OUTPUT_DIR)
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${FIXPOINT_PLUGIN_OUTPUT_DIR})
  endif()
  set_property(GLOBAL APPEND PROPERTY FIXPOINT_PLUGIN_TARGETS ${name})
  if(DEFINED FIXPOINT_PLUGIN_INSTALL_DIR)
    # (Built with it: see the top CMakeLists.txt, on RUNPATHs.)
    set_target_properties(${name} PROPERTIES INSTALL_RPATH "$ORIGIN/../.." BUILD_WITH_INSTALL_RPATH ON)
    install(TARGETS ${name} LIBRARY DESTINATION ${FIXPOINT_PLUGIN_INSTALL_DIR})
  endif()
endfunction()
