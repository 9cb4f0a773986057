# `cmake --install build --prefix P`: the five executables, the model libraries, their headers (under
# P/include/debris, with the source tree's paths: #include "scenarios/common/dem/dem_simulation.hpp") and
# a CMake package, so that another project builds against debris:
#   find_package(debris REQUIRED)
#   target_link_libraries(app PRIVATE debris::dem)      # or debris::peridem, debris::core, ...
# The libraries are static; the package finds what they link (OpenMP, yaml-cpp, Eigen, CLI11; HDF5 comes as
# debris::hdf5 with the paths of the build, so the consumer needs neither FindHDF5 nor the C language; FFTW
# likewise as debris::fftw).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(_debris_libraries debris_openmp debris_hdf5 debris_fftw debris_core debris_kernels_dem debris_kernels_peridem debris_run debris_dem_sim
    debris_peridem_sim)
# The names another project links: debris::core, debris::kernels_dem, ..., debris::dem, debris::peridem.
set_target_properties(debris_dem_sim PROPERTIES EXPORT_NAME dem)
set_target_properties(debris_peridem_sim PROPERTIES EXPORT_NAME peridem)
foreach(_t debris_openmp debris_hdf5 debris_fftw debris_core debris_kernels_dem debris_kernels_peridem debris_run)
  string(REPLACE "debris_" "" _name ${_t})
  set_target_properties(${_t} PROPERTIES EXPORT_NAME ${_name})
endforeach()

install(TARGETS debris_dem debris_peridem debris_patch debris_amorphous debris_restitution debris_calibrate
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ${_debris_libraries} EXPORT debrisTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/debris)
foreach(_dir core kernels scenarios/common)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${_dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/debris/${_dir}
          FILES_MATCHING PATTERN "*.hpp")
endforeach()
install(EXPORT debrisTargets NAMESPACE debris:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/debris)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/debrisConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/debrisConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/debris)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/debrisConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/debrisConfig.cmake ${PROJECT_BINARY_DIR}/debrisConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/debris)
