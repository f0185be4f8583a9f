# ctest script: installs the build tree into a scratch prefix, builds examples/find_package
# against it with find_package(npf), and runs the result on the shipped material.
file(REMOVE_RECURSE "${WORK_DIR}")
function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()
run_step("install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
foreach(header npf/core/brdf.h npf/materials/rgl_brdf.h npf/materials/open_material.h
               npf/shading/npf_brdf.h npf/shading/npf_texture_file.h)
  if(NOT EXISTS "${WORK_DIR}/prefix/include/${header}")
    message(FATAL_ERROR "installed tree lacks include/${header}")
  endif()
endforeach()
run_step("configure consumer" ${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/find_package"
         -B "${WORK_DIR}/consumer" -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
run_step("build consumer" ${CMAKE_COMMAND} --build "${WORK_DIR}/consumer")
run_step("run consumer" "${WORK_DIR}/consumer/npf_consumer"
         "${SOURCE_DIR}/data/materials/ilm_l3_37_metallic_rgb.bsdf")
if(NOT step_output MATCHES "format rgl, channels R G B")
  message(FATAL_ERROR "unexpected consumer output: ${step_output}")
endif()
message(STATUS "consumer: ${step_output}")
