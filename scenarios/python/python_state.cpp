#include "scenarios/python/python_state.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

#include "core/error.hpp"
#include "core/unique_ids.hpp"
#include "kernels/dem/cohesive_material.hpp"
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

namespace {

void check_dem_edit(const DemSimulation& sim, const std::vector<std::string>& written) {
  const Particles& p = sim.particles();
  for (const std::string& name : written) {
    p.check_column(name, "state." + name);
    if (name != "group") continue;
    const std::size_t groups = sim.groups().list.size();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.group[i] >= static_cast<int>(groups))
        throw input_error("state.group", std::to_string(p.group[i]),
                          (groups == 0 ? std::string("must be -1: this system has no groups")
                                       : "must be -1 (no group) or a group's index, 0 to " + std::to_string(groups - 1)) +
                              " (particle id " + std::to_string(p.id[i]) + " at index " + std::to_string(i) + ")");
  }
  const auto wrote = [&written](const char* name) { return std::find(written.begin(), written.end(), name) != written.end(); };
  // The neighbour search's reach (the cutoff of two of the largest particles, delta_f included) is fixed at
  // set-up: a particle grown past it would lose pairs, and the list's next build refuses it mid-run.
  if (wrote("radius") && p.size() > 0) {
    const auto largest = std::max_element(p.radius.begin(), p.radius.end());
    const std::size_t i = static_cast<std::size_t>(largest - p.radius.begin());
    const double r = *largest;
    if (CohesiveCutoff{sim.coefficients()}(r, r) > sim.max_cutoff() * (1.0 + 1e-12))
      throw input_error("state.radius", format_value(r),
                        "makes particle id " + std::to_string(p.id[i]) + " (index " + std::to_string(i) +
                            ") larger than the largest particle at set-up: the neighbour search's reach, " +
                            format_value(sim.max_cutoff()) + " for two of them, is fixed then; give the larger "
                            "radius in the input");
  }
  // A smaller radius or a lighter particle shortens eq 6's critical time step, which the input's time step
  // was checked against at set-up.
  if ((wrote("radius") || wrote("mass")) && !sim.settings().allow_unstable_time_step) {
    const StabilityLimits limits = stability_limits(sim.coefficients(), p);
    if (sim.dt() > limits.dt_c) {
      const std::size_t i = static_cast<std::size_t>(limits.particle);
      const bool by_mass = wrote("mass");
      throw input_error(by_mass ? "state.mass" : "state.radius", format_value(by_mass ? p.mass[i] : p.radius[i]),
                        "gives particle id " + std::to_string(p.id[i]) + " (index " + std::to_string(i) +
                            ") the critical time step dt_c = " + format_value(limits.dt_c) + " of eq 6, below the run's "
                            "time step " + format_value(sim.dt()) + " (semi-implicit Euler diverges above it; "
                            "run.allow_unstable_time_step: true insists)");
    }
  }
}

void check_peridem_edit(const PeridemSimulation& sim, const std::vector<std::string>& written) {
  const PdNodes& n = sim.nodes();
  const PdGrains& g = sim.grains();
  const auto which = [&n](std::size_t i) {
    return " (node id " + std::to_string(n.id[i]) + " at index " + std::to_string(i) + ")";
  };
  for (const std::string& name : written) {
    const std::string key = "state." + name;
    if (name == "id") {
      require_unique_ids(n.id, key, "node");
      continue;
    }
    if (name == "grain") {
      // Bonds, contacts and per-grain sums go by each grain's contiguous range of nodes.
      for (std::size_t k = 0; k < g.size(); ++k)
        for (int i = g.node_begin[k]; i < g.node_end[k]; ++i)
          if (n.grain[static_cast<std::size_t>(i)] != static_cast<int>(k))
            throw input_error(key, std::to_string(n.grain[static_cast<std::size_t>(i)]),
                              "a node's grain is its place in the grains' node ranges: this node is grain " +
                                  std::to_string(k) + "'s and stays so" + which(static_cast<std::size_t>(i)));
      continue;
    }
    if (name == "fixed") {
      for (std::size_t i = 0; i < n.size(); ++i)
        if (n.fixed[i] < 0 || n.fixed[i] > 7)
          throw input_error(key, std::to_string(n.fixed[i]), "must be a mask of fixed components, 0 to 7 (1 x, 2 y, 4 z)" + which(i));
      continue;
    }
    // Volume and mass divide (accelerations, eq 7's weighted volume); set-up requires volume > 0.
    const bool positive = name == "volume" || name == "mass" || name == "weighted_volume";
    n.for_each_column([&](const char* c, const auto& col) {
      if (name != c) return;
      if constexpr (std::is_floating_point_v<std::decay_t<decltype(col[0])>>)
        for (std::size_t i = 0; i < col.size(); ++i) {
          if (!std::isfinite(col[i])) throw input_error(key, format_value(col[i]), "must be finite" + which(i));
          if (positive && !(col[i] > 0)) throw input_error(key, format_value(col[i]), "must be > 0" + which(i));
        }
    });
  }
}

}  // namespace

void check_state_edit(PyRun& run, const std::vector<std::string>& written) {
  if (run.kind() == PyModel::dem)
    check_dem_edit(std::as_const(dem_simulation(run.model())), written);
  else
    check_peridem_edit(std::as_const(peridem_simulation(run.model())), written);
}

double begin_state_edit(PyRun& run) {
  return run.kind() == PyModel::dem ? std::as_const(dem_simulation(run.model())).energy_content() : 0.0;
}

void end_state_edit(PyRun& run, const std::vector<std::string>& written, bool positions_changed, double content_before) {
  check_state_edit(run, written);
  if (run.kind() == PyModel::dem) {
    DemSimulation& sim = dem_simulation(run.model());
    Particles& p = sim.particles();  // marks the host copy changed (offload builds), whatever was written
    // A group's count and mass (a rigid group's motion) follow its members' group and mass.
    if (std::find_if(written.begin(), written.end(), [](const std::string& n) { return n == "group" || n == "mass"; }) !=
        written.end())
      sim.groups().refresh_members(p);
    if (positions_changed) sim.rebuild_neighbors();
    sim.recompute_forces();
    // What the edit did to the energy content is work done on the system, as a stage's changes are.
    if (sim.settings().energy_accounting) sim.add_stage_work(std::as_const(sim).energy_content() - content_before);
    return;
  }
  PeridemSimulation& sim = peridem_simulation(run.model());
  sim.nodes();
  sim.recompute_forces();  // rebuilds the contact list too
}

}  // namespace debris
