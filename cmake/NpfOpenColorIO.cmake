# npf_find_opencolorio(): makes the imported target OpenColorIO::OpenColorIO (OpenColorIO 2.1 or
# later) available, for this project and for projects that find_package(npf).
#
# Debian 12's libopencolorio-dev installs its CMake package files straight into /usr/share/cmake/,
# where find_package() does not look, and those files compute their prefix as "/" from there (the
# target would name /include, which does not exist, and CMake refuses it). So: the package config
# when it is found and sane; otherwise the header and library are found directly, with
# pkg-config's folders as hints when pkg-config is present.
# A macro, so that the imported target lands in the caller's directory scope.
macro(npf_find_opencolorio)
  if(NOT TARGET OpenColorIO::OpenColorIO)
    find_package(OpenColorIO 2.1 CONFIG QUIET)
  endif()
  set(_npf_ocio_usable FALSE)
  if(TARGET OpenColorIO::OpenColorIO)
    set(_npf_ocio_usable TRUE)
    get_target_property(_npf_ocio_dirs OpenColorIO::OpenColorIO INTERFACE_INCLUDE_DIRECTORIES)
    foreach(_npf_ocio_dir IN LISTS _npf_ocio_dirs)
      if(NOT EXISTS "${_npf_ocio_dir}")
        set(_npf_ocio_usable FALSE)
      endif()
    endforeach()
  endif()
  if(NOT _npf_ocio_usable)
    find_package(PkgConfig QUIET)
    if(PKG_CONFIG_FOUND)
      pkg_check_modules(_npf_ocio_pc QUIET OpenColorIO)
    endif()
    find_path(NPF_OPENCOLORIO_INCLUDE_DIR OpenColorIO/OpenColorIO.h HINTS ${_npf_ocio_pc_INCLUDE_DIRS})
    find_library(NPF_OPENCOLORIO_LIBRARY NAMES OpenColorIO HINTS ${_npf_ocio_pc_LIBRARY_DIRS})
    if(NOT NPF_OPENCOLORIO_INCLUDE_DIR OR NOT NPF_OPENCOLORIO_LIBRARY)
      message(FATAL_ERROR "OpenColorIO 2.1 or later not found (Debian: apt-get install libopencolorio-dev)")
    endif()
    file(STRINGS "${NPF_OPENCOLORIO_INCLUDE_DIR}/OpenColorIO/OpenColorABI.h" _npf_ocio_version_line
         REGEX "^#define OCIO_VERSION_STR[ \t]+\"[0-9.]+\"")
    string(REGEX MATCH "[0-9]+\\.[0-9]+(\\.[0-9]+)?" _npf_ocio_version "${_npf_ocio_version_line}")
    if(_npf_ocio_version AND _npf_ocio_version VERSION_LESS 2.1)
      message(FATAL_ERROR "OpenColorIO ${_npf_ocio_version} found in ${NPF_OPENCOLORIO_INCLUDE_DIR}; npf needs 2.1 or later")
    endif()
    if(TARGET OpenColorIO::OpenColorIO)
      # A package config with a wrong prefix: keep its target, point it at what was found.
      set_target_properties(OpenColorIO::OpenColorIO PROPERTIES
        INTERFACE_INCLUDE_DIRECTORIES "${NPF_OPENCOLORIO_INCLUDE_DIR}")
      foreach(_npf_ocio_config IN ITEMS "" _RELEASE _RELWITHDEBINFO _MINSIZEREL _DEBUG _NOCONFIG)
        set_target_properties(OpenColorIO::OpenColorIO PROPERTIES
          IMPORTED_LOCATION${_npf_ocio_config} "${NPF_OPENCOLORIO_LIBRARY}")
      endforeach()
    else()
      add_library(OpenColorIO::OpenColorIO UNKNOWN IMPORTED)
      set_target_properties(OpenColorIO::OpenColorIO PROPERTIES
        IMPORTED_LOCATION "${NPF_OPENCOLORIO_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${NPF_OPENCOLORIO_INCLUDE_DIR}")
    endif()
  endif()
endmacro()
