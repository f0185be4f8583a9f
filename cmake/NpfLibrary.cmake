# npf_add_library(NAME SOURCES...): one of npf's libraries, npf_NAME, as every module declares it:
# the alias npf::NAME, its public headers in include/ (installed under include/npf/), the export
# set npfTargets and the project's warnings. Each module's CMakeLists.txt adds only what is its
# own (dependencies, definitions, per-file flags).
function(npf_add_library name)
  set(target npf_${name})
  add_library(${target} ${ARGN})
  add_library(npf::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ${target})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:npf_warnings>)
  install(TARGETS ${target} EXPORT npfTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/npf DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# npf_x86_simd_sources(AVX2|AVX2_FMA|PORTABLE [EXTRA flags...] FILES f...): the compile flags of
# the files built for one instruction set, chosen at run time (npf/core/simd_isa.h).
#   AVX2      -mavx2 without FMA and without contraction: the same bits as the portable build,
#             which results that must not move (fit, double lanes, analytic Fresnel) require.
#   AVX2_FMA  -mavx2 -mfma with contraction: the float lanes, within their error budget
#             (docs/shading.md); run only where the CPU has FMA.
#   PORTABLE  no contraction (the twin of an AVX2 file that must give the same bits).
# EXTRA adds flags of the files' own. GCC or Clang only; on other compilers nothing is set.
function(npf_x86_simd_sources kind)
  cmake_parse_arguments(arg "" "" "EXTRA;FILES" ${ARGN})
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    return()
  endif()
  if(kind STREQUAL "PORTABLE")
    set(flags -ffp-contract=off)
  elseif(NOT CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64|i.86")
    return()
  elseif(kind STREQUAL "AVX2")
    set(flags -mavx2 -mno-fma -ffp-contract=off)
  elseif(kind STREQUAL "AVX2_FMA")
    set(flags -mavx2 -mfma -ffp-contract=fast)
  else()
    message(FATAL_ERROR "npf_x86_simd_sources: unknown kind ${kind}")
  endif()
  set_source_files_properties(${arg_FILES} PROPERTIES COMPILE_OPTIONS "${arg_EXTRA};${flags}")
endfunction()

# npf_shipped_file(DEFINE PREFIX FOR source.cpp FILE path INSTALL_DIR dir [ALSO files...]): a data
# file npf ships (the default environment map, the OCIO config), found at run time beside an
# installed executable (relative path), in this source tree (build trees), or under the configured
# install prefix: `source.cpp` gets PREFIX_SOURCE, PREFIX_INSTALLED and PREFIX_FROM_BINDIR; the
# file (and ALSO, e.g. its README) is installed into INSTALL_DIR under the data directory.
function(npf_shipped_file)
  cmake_parse_arguments(arg "" "DEFINE;FOR;FILE;INSTALL_DIR" "ALSO" ${ARGN})
  get_filename_component(name ${arg_FILE} NAME)
  set(installed ${CMAKE_INSTALL_FULL_DATADIR}/${arg_INSTALL_DIR}/${name})
  file(RELATIVE_PATH from_bindir ${CMAKE_INSTALL_FULL_BINDIR} ${installed})
  set_property(SOURCE ${arg_FOR} APPEND PROPERTY COMPILE_DEFINITIONS
    ${arg_DEFINE}_SOURCE="${PROJECT_SOURCE_DIR}/${arg_FILE}"
    ${arg_DEFINE}_INSTALLED="${installed}"
    ${arg_DEFINE}_FROM_BINDIR="${from_bindir}")
  set(also)
  foreach(f ${arg_ALSO})
    list(APPEND also ${PROJECT_SOURCE_DIR}/${f})
  endforeach()
  install(FILES ${PROJECT_SOURCE_DIR}/${arg_FILE} ${also} DESTINATION ${CMAKE_INSTALL_DATADIR}/${arg_INSTALL_DIR})
endfunction()
