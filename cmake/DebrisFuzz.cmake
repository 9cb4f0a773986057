# -DDEBRIS_FUZZ=ON: the coverage-guided fuzzer of the readers of outside data (tests/fuzz). The readers'
# sources get GCC's -fsanitize-coverage=trace-pc (an edge counter per basic block, tests/fuzz/coverage.cpp,
# compiled into debris_core), and tests/fuzz adds debris_fuzz and its ctest tests (label "fuzz"). Meant for
# the sanitizer build (-DDEBRIS_SANITIZE=ON), where a bad read or write in a reader stops the fuzzer.
if(NOT DEBRIS_FUZZ)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "DEBRIS_FUZZ needs g++ or clang++ (-fsanitize-coverage=trace-pc)")
endif()

target_sources(debris_core PRIVATE ${PROJECT_SOURCE_DIR}/tests/fuzz/coverage.cpp)

function(debris_fuzz_instrument target)
  foreach(src IN LISTS ARGN)
    set_property(SOURCE ${src} TARGET_DIRECTORY ${target} APPEND PROPERTY COMPILE_OPTIONS -fsanitize-coverage=trace-pc)
  endforeach()
endfunction()
set(_core ${PROJECT_SOURCE_DIR}/core)
set(_common ${PROJECT_SOURCE_DIR}/scenarios/common)
debris_fuzz_instrument(debris_core ${_core}/io/input.cpp ${_core}/units.cpp ${_core}/io/lammps_data.cpp
                       ${_core}/io/gmsh_msh.cpp ${_core}/io/grain_csv.cpp ${_core}/io/hdf5_file.cpp ${_core}/region.cpp
                       ${_core}/rough/height_map_file.cpp
                       ${_core}/lattice.cpp)
debris_fuzz_instrument(debris_dem_sim ${_common}/dem/dem_input.cpp ${_common}/dem/dem_checkpoint.cpp)
debris_fuzz_instrument(debris_peridem_sim ${_common}/peridem/peridem_input.cpp ${_common}/peridem/peridem_checkpoint.cpp)
debris_fuzz_instrument(debris_run ${_common}/run/stages.cpp)
debris_fuzz_instrument(debris_patch_input ${PROJECT_SOURCE_DIR}/scenarios/patch/patch_input.cpp)
debris_fuzz_instrument(debris_amorphous_input ${PROJECT_SOURCE_DIR}/scenarios/amorphous/amorphous_input.cpp)
debris_fuzz_instrument(debris_restitution_input ${PROJECT_SOURCE_DIR}/scenarios/restitution/restitution_input.cpp)

add_subdirectory(${PROJECT_SOURCE_DIR}/tests/fuzz ${CMAKE_BINARY_DIR}/tests/fuzz)
message(STATUS "debris: DEBRIS_FUZZ=ON (debris_fuzz, ctest -L fuzz)")
