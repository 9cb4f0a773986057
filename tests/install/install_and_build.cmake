# ctest InstallPackage.FindPackageBuildsAndRunsAnApp: cmake -DBUILD=<debris build> -DSOURCE=<tests/install>
# -DWORK=<scratch> -P install_and_build.cmake. Installs debris from BUILD into WORK/prefix, configures and
# builds the consumer project in SOURCE against it (C++ only, no standard set), and runs its programs (one on
# the DEM model, one on PeriDEM, one making a rough surface with FFTW).
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix RESULT_VARIABLE rc
                OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
foreach(f bin/debris_dem bin/debris_peridem include/debris/scenarios/common/dem/dem_simulation.hpp
          include/debris/core/rough/self_affine_surface.hpp lib/cmake/debris/debrisConfig.cmake)
  if(NOT EXISTS ${WORK}/prefix/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/app -DCMAKE_PREFIX_PATH=${WORK}/prefix
                        -DCMAKE_BUILD_TYPE=Release
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the consumer failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/app RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the consumer failed:\n${out}\n${err}")
endif()
foreach(app pull_apart drop rough)
  execute_process(COMMAND ${WORK}/app/${app} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${app}: ${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the consumer ${app} failed (${rc}):\n${out}\n${err}")
  endif()
endforeach()
