#pragma once
// The state of a run as numpy arrays over its live columns, without copies: the DEM particles' columns
// (core/particles.hpp) and the PeriDEM nodes' (core/pd_nodes.hpp), one 1-D array per column, as they are
// stored (structure of arrays). Each array is made at the moment it is asked for, from the host copy made
// current first (offload builds bring it back from the device), and holds a reference to its simulation so
// the memory outlives it. Read-only unless asked for inside an edit; an edit marks the host copy changed, so
// offload builds send it to the device before the next kernel, and re-evaluates this step's forces (the
// same calls a stage's changes make).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "scenarios/python/python_run.hpp"

namespace debris {

/// The column names of a model's state, in storage order.
std::vector<std::string> state_columns(PyModel model);

/// Column `name` as a 1-D numpy array over the live memory; `owner` is kept alive by it. KeyError for an
/// unknown name. PeriDEM's `damage` is brought up to date first (eq 14 for the current positions).
pybind11::array state_column(PyRun& run, const std::string& name, bool writable, pybind11::handle owner);

/// The columns an edit wrote (`written`), checked as the input's values are at set-up: InputError naming
/// 'state.<column>', the value and the item (DEM: Particles::check_column, a group index within the groups,
/// the time step still below eq 6's dt_c for the edited radii and masses; PeriDEM: finite values, volume,
/// mass and weighted volume > 0, ids unique, each node in the grain its place gives it, `fixed` a mask of
/// x, y, z). Nothing is changed; the caller puts the columns back when it throws.
void check_state_edit(PyRun& run, const std::vector<std::string>& written);

/// The end of an edit: the written columns checked (check_state_edit), then the host copy marked changed
/// (offload builds), the neighbour or contact list rebuilt when positions may have moved
/// (`positions_changed`), and this step's forces evaluated again.
/// The energy content (DemSimulation::energy_content) before an edit: end_state_edit counts its change as
/// work done on the system, as a stage's changes are (0 for PeriDEM).
double begin_state_edit(PyRun& run);
void end_state_edit(PyRun& run, const std::vector<std::string>& written, bool positions_changed, double content_before);

}  // namespace debris
