# find_package(OpenImageIO) for this project. Debian 12's OpenImageIO package lists
# /usr/include/opencv4 in its CMake targets without depending on OpenCV, and CMake refuses an
# imported target whose include folder is missing. Folders that do not exist are dropped.
# A macro, so that the imported targets land in the caller's directory scope.
macro(npf_find_openimageio)
  find_package(OpenImageIO CONFIG REQUIRED)
  foreach(_npf_oiio_target OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
    if(TARGET ${_npf_oiio_target})
      foreach(_npf_oiio_property INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
        get_target_property(_npf_oiio_dirs ${_npf_oiio_target} ${_npf_oiio_property})
        if(_npf_oiio_dirs)
          set(_npf_oiio_kept "")
          foreach(_npf_oiio_dir IN LISTS _npf_oiio_dirs)
            if(EXISTS "${_npf_oiio_dir}")
              list(APPEND _npf_oiio_kept "${_npf_oiio_dir}")
            endif()
          endforeach()
          set_target_properties(${_npf_oiio_target} PROPERTIES ${_npf_oiio_property} "${_npf_oiio_kept}")
        endif()
      endforeach()
    endif()
  endforeach()
endmacro()
