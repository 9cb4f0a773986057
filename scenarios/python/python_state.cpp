#include "scenarios/python/python_state.hpp"

#include <type_traits>
#include <utility>

#include "scenarios/common/dem/dem_run.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/peridem/peridem_run.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"

namespace debris {

namespace py = pybind11;

namespace {

template <class Columns>
std::vector<std::string> names_of(const Columns& c) {
  std::vector<std::string> names;
  c.for_each_column([&](const char* name, const auto&) { names.emplace_back(name); });
  return names;
}

/// The column `name` of `columns` (Particles or PdNodes) as an array over its memory.
template <class Columns>
py::array column_array(const Columns& columns, const std::string& name, bool writable, py::handle owner) {
  py::array out;
  bool found = false;
  columns.for_each_column([&](const char* n, const auto& col) {
    if (found || name != n) return;
    found = true;
    using T = std::decay_t<decltype(col[0])>;
    out = py::array(py::dtype::of<T>(), {static_cast<py::ssize_t>(col.size())}, {static_cast<py::ssize_t>(sizeof(T))},
                    col.data(), owner);
  });
  if (!found) {
    std::string known;
    for (const std::string& n : names_of(columns)) known += (known.empty() ? "" : ", ") + n;
    throw py::key_error("'" + name + "': no such column (columns: " + known + ")");
  }
  if (!writable) out.attr("setflags")(py::arg("write") = false);
  return out;
}

}  // namespace

std::vector<std::string> state_columns(PyModel model) {
  return model == PyModel::dem ? names_of(Particles{}) : names_of(PdNodes{});
}

py::array state_column(PyRun& run, const std::string& name, bool writable, py::handle owner) {
  if (run.kind() == PyModel::dem) {
    DemSimulation& sim = dem_simulation(run.model());
    // The non-const accessor marks the host copy edited (offload builds), so only an edit takes it.
    if (writable) return column_array(sim.particles(), name, true, owner);
    return column_array(std::as_const(sim).particles(), name, false, owner);
  }
  PeridemSimulation& sim = peridem_simulation(run.model());
  if (name == "damage") sim.refresh_damage();
  if (writable) return column_array(sim.nodes(), name, true, owner);
  return column_array(std::as_const(sim).nodes(), name, false, owner);
}

void end_state_edit(PyRun& run, bool positions_changed) {
  if (run.kind() == PyModel::dem) {
    DemSimulation& sim = dem_simulation(run.model());
    sim.particles();  // marks the host copy changed (offload builds), whatever was written
    if (positions_changed) sim.rebuild_neighbors();
    sim.recompute_forces();
    return;
  }
  PeridemSimulation& sim = peridem_simulation(run.model());
  sim.nodes();
  sim.recompute_forces();  // rebuilds the contact list too
}

}  // namespace debris
