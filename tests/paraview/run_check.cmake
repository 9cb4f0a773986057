# The ParaViewOpensTrajectory test: write_sample writes DIR/sample.{h5,xmf} and DIR/expected.json, then
# ParaView's pvpython opens the .xmf with check_trajectory.py, headless.
#   cmake -DWRITER=... -DPVPYTHON=... -DSCRIPT=... -DDIR=... [-DLAUNCH="mpiexec;-np;3;..."] -P run_check.cmake
# LAUNCH (a list) starts the writer, e.g. under mpiexec: the ranks then write the trajectory together.
if(NOT PVPYTHON OR PVPYTHON MATCHES "NOTFOUND$")
  # Failing, not skipping: CI installs ParaView, and a silent skip there would hide a broken trajectory.
  message(FATAL_ERROR "pvpython not found: install ParaView's Python (Debian 12: "
                      "apt-get install --no-install-recommends python3-paraview) and re-run cmake; where "
                      "ParaView cannot be installed, configure with -DDEBRIS_PARAVIEW_TEST=OFF or run ctest -LE paraview")
endif()

file(REMOVE_RECURSE "${DIR}")
file(MAKE_DIRECTORY "${DIR}")
execute_process(COMMAND ${LAUNCH} "${WRITER}" "${DIR}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${WRITER} ${DIR} failed: ${rc}")
endif()

# No X server here or on CI: without DISPLAY and with offscreen rendering VTK never looks for one.
unset(ENV{DISPLAY})
execute_process(COMMAND "${PVPYTHON}" --force-offscreen-rendering "${SCRIPT}" "${DIR}/sample.xmf" "${DIR}/expected.json"
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ParaView does not show the trajectory as written (check_trajectory.py: ${rc})")
endif()
