// The compiled half of `import debris` (the module _debris): a run of either model as the executables make
// it (python_run), its state as numpy arrays (python_state), and its diagnostics as Python values. The
// Python half (debris/__init__.py) wraps it in the classes users see: Dem, Peridem, their views and edits.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "kernels/dem/integrate.hpp"
#include "scenarios/common/dem/dem_run.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/dem/surface_census.hpp"
#include "scenarios/common/dem/wear_analysis.hpp"
#include "scenarios/common/peridem/peridem_run.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "scenarios/python/python_input.hpp"
#include "scenarios/python/python_run.hpp"
#include "scenarios/python/python_state.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace debris {
namespace {

// Tags for the Python exception types (py::exception needs a C++ type; nothing is thrown as these).
struct InputErrorTag {};
struct RunStoppedTag {};
struct StaleViewTag {};

py::tuple vec(const Vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

PyModel model_of(const std::string& kind) {
  if (kind == "dem") return PyModel::dem;
  if (kind == "peridem") return PyModel::peridem;
  throw py::value_error("model '" + kind + "': dem or peridem");
}

void require(const PyRun& r, PyModel m) {
  if (r.kind() != m) throw py::type_error(m == PyModel::dem ? "a DEM run's value" : "a PeriDEM run's value");
}

py::dict progress_dict(const Run& run) {
  const ProgressValues p = run.progress();
  return py::dict("first_step"_a = p.first_step, "step"_a = p.step, "last_step"_a = p.last_step,
                  "fraction"_a = p.last_step > p.first_step
                                     ? static_cast<double>(p.step - p.first_step) / static_cast<double>(p.last_step - p.first_step)
                                     : 1.0,
                  "seconds"_a = p.seconds, "steps_per_second"_a = p.steps_per_second, "seconds_left"_a = p.seconds_left);
}

py::dict pass_table_dict(const Run& run) {
  const PassTable t = run.pass_table();
  py::list rows;
  for (const PassTime& r : t.rows)
    rows.append(py::dict("name"_a = r.name, "seconds"_a = r.seconds, "share"_a = t.total > 0 ? r.seconds / t.total : 0.0,
                         "note"_a = r.note));
  return py::dict("rows"_a = rows, "total"_a = t.total, "stepping"_a = t.stepping, "steps"_a = t.steps,
                  "items_steps_per_second"_a = t.items_steps_per_second, "bytes_per_step"_a = t.bytes_per_step);
}

py::dict wear_sample_dict(const WearSample& s) {
  py::dict d;
  const std::vector<std::string> cols = WearAnalysis::columns();
  const std::vector<double> row = WearAnalysis::row(s);
  for (std::size_t k = 0; k < cols.size() && k < row.size(); ++k) d[py::str(cols[k])] = row[k];
  d["sample_verdict"] = verdict_name(s.sample_verdict);
  d["verdict"] = verdict_name(s.verdict);
  return d;
}

}  // namespace
}  // namespace debris

PYBIND11_MODULE(_debris, m) {
  using namespace debris;
  m.doc() = "debris's compiled core: use the classes of the debris package (debris.Dem, debris.Peridem)";

  PyErrors& errors = py_errors();
  errors.input_error = py::exception<InputErrorTag>(m, "InputError", PyExc_ValueError);
  errors.run_stopped = py::exception<RunStoppedTag>(m, "RunStopped", PyExc_RuntimeError);
  errors.stale_view = py::exception<StaleViewTag>(m, "StaleViewError", PyExc_RuntimeError);
  // An input error is raised with the executable's message; an output that cannot be written stops the run.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(py_errors().input_error.ptr(), e.what());
    } catch (const OutputError& e) {
      PyErr_SetString(py_errors().run_stopped.ptr(), e.what());
    }
  });

  m.def("yaml_from_dict", [](const py::dict& d) { return yaml_from_python(d); },
        "The YAML text a dict input is read as (what a checkpoint keeps)");
  m.def("load_input", &python_from_yaml_file, "path"_a,
        "An input file as a dict: numbers, true/false and null as Python values, quantities (\"73 GPa\") as str");
  m.def("offload_build", [] { return exec::offload_build(); }, "Whether kernels run on an offload device");
  m.def("columns", [](const std::string& kind) { return state_columns(model_of(kind)); }, "kind"_a);

  py::class_<PyRun>(m, "_Run")
      .def(py::init([](const std::string& kind, const std::string& input, py::object values, const std::string& restart,
                       const std::string& output, const std::string& base_directory, int threads, bool quiet) {
             PyRunArgs a;
             a.input = input;
             a.values = std::move(values);
             a.restart = restart;
             a.output = output;
             a.base_directory = base_directory;
             a.threads = threads;
             a.quiet = quiet;
             return std::make_unique<PyRun>(model_of(kind), a);
           }),
           "kind"_a, "input"_a, "values"_a, "restart"_a, "output"_a, "base_directory"_a, "threads"_a, "quiet"_a)
      .def("advance", &PyRun::advance, "steps"_a)
      .def("advance_stage", &PyRun::advance_stage)
      .def("finish", &PyRun::finish)
      .def_property_readonly("finished", &PyRun::finished)
      .def_property_readonly("report", &PyRun::report)
      .def("checkpoint", &PyRun::checkpoint, "path"_a)
      .def("generation", &PyRun::generation)
      .def_property_readonly("step", [](PyRun& r) { return r.model().step_count(); })
      .def_property_readonly("time", [](PyRun& r) { return r.model().time(); })
      .def_property_readonly("last_step", [](PyRun& r) { return r.run().last_step(); })
      .def_property_readonly("done", [](PyRun& r) { return r.run().done(); })
      .def_property_readonly("directory", [](PyRun& r) { return r.run().directory(); })
      .def_property_readonly("checkpoint_path", [](PyRun& r) { return r.run().checkpoint_path(); })
      .def_property_readonly("input_text", [](PyRun& r) { return r.run().plan().input_text; })
      .def_property_readonly("dt", [](PyRun& r) { return r.run().plan().dt; })
      .def_property_readonly("items", [](PyRun& r) { return r.model().items(); })
      .def_property_readonly("stop_message", [](PyRun& r) { return r.run().stop_message(); })
      .def("thermo_columns", [](PyRun& r) { return r.model().thermo_columns(); })
      .def("thermo_row", [](PyRun& r) { return r.model().thermo_row(); })
      .def("stages",
           [](PyRun& r) {
             const StagePlan& st = r.run().stages();
             py::list out;
             for (std::size_t k = 0; k < st.start.size(); ++k)
               out.append(py::dict("name"_a = st.names[k], "start"_a = st.start[k],
                                   "end"_a = k + 1 < st.start.size() ? st.start[k + 1] : st.end));
             return out;
           })
      .def("progress", [](PyRun& r) { return progress_dict(r.run()); })
      .def("pass_table", [](PyRun& r) { return pass_table_dict(r.run()); })
      .def("column",
           [](PyRun& r, const std::string& name, bool writable, py::handle owner) {
             return state_column(r, name, writable, owner);
           },
           "name"_a, "writable"_a, "owner"_a)
      .def("begin_edit", &begin_state_edit)
      .def("end_edit", &end_state_edit, "written"_a, "positions_changed"_a, "content_before"_a)
      .def("dem_energy",
           [](PyRun& r) -> py::object {
             require(r, PyModel::dem);
             const DemSimulation& sim = dem_simulation(r.model());
             if (!sim.settings().energy_accounting) return py::none();
             const EnergyBalance b = sim.energy_balance(sim.diagnostics());
             py::dict drives;
             for (std::size_t k = 0; k < sim.groups().size(); ++k)
               drives[py::str(sim.groups().list[k].name)] = b.totals.drive_work[k];
             return py::dict("work_in"_a = b.work_in(), "work_drives"_a = drives, "work_stages"_a = b.stage_work,
                             "kinetic_energy"_a = b.kinetic, "kinetic_energy_start"_a = b.kinetic0,
                             "elastic_energy"_a = b.elastic, "elastic_energy_start"_a = b.elastic0,
                             "dissipated_normal"_a = b.totals.dissipated_normal,
                             "dissipated_tangential"_a = b.totals.dissipated_tangential,
                             "dissipated_sliding"_a = b.totals.dissipated_sliding,
                             "dissipated_global"_a = b.totals.dissipated_global,
                             "tangential_work"_a = b.totals.tangential_work, "residual"_a = b.residual());
           })
      // DEM.
      .def("dem_groups",
           [](PyRun& r) {
             require(r, PyModel::dem);
             py::list out;
             for (const Group& g : dem_simulation(r.model()).groups().list)
               out.append(py::dict("name"_a = g.name, "motion"_a = motion_name(g.motion), "velocity"_a = vec(g.velocity),
                                   "external_force"_a = vec(g.external_force), "count"_a = g.count, "mass"_a = g.mass,
                                   "reaction"_a = vec(g.reaction), "displacement"_a = vec(g.displacement)));
             return out;
           })
      .def("dem_diagnostics",
           [](PyRun& r) {
             require(r, PyModel::dem);
             const DemSimulation& sim = dem_simulation(r.model());
             const CohesiveDiagnostics d = sim.diagnostics();
             return py::dict("kinetic_energy"_a = particle_totals(sim.particles()).kinetic_energy,
                             "elastic_energy"_a = d.elastic_energy, "max_overlap"_a = d.max_overlap,
                             "interacting_pairs"_a = d.interacting_pairs, "rebuilds"_a = sim.times().rebuilds,
                             "layout_generation"_a = sim.layout_generation());
           })
      .def("dem_wear",
           [](PyRun& r) -> py::object {
             require(r, PyModel::dem);
             const WearAnalysis* w = dem_wear_analysis(r.model());
             if (!w) return py::none();
             py::list samples;
             for (const WearSample& s : w->samples()) samples.append(wear_sample_dict(s));
             return py::dict("verdict"_a = verdict_name(w->verdict()), "report"_a = w->report(),
                             "detection_index"_a = w->detection_index(), "samples"_a = samples,
                             "last"_a = w->samples().empty() ? py::object(py::none())
                                                             : py::object(wear_sample_dict(w->samples().back())));
           })
      .def("dem_surfaces",
           [](PyRun& r) -> py::object {
             require(r, PyModel::dem);
             const SurfaceCensus* c = dem_surface_census(r.model());
             if (!c) return py::none();
             // Each sample as surfaces.csv's row, by column name; the histograms as surfaces_histogram.csv's.
             const std::vector<std::string> names = SurfaceCensus::columns(), hist = SurfaceCensus::histogram_columns();
             py::list samples;
             for (const SurfaceSample& s : c->samples()) {
               const std::vector<double> row = SurfaceCensus::row(s);
               py::dict d;
               for (std::size_t k = 0; k < names.size() && k < row.size(); ++k) d[py::str(names[k])] = row[k];
               py::list bins;
               for (const std::vector<double>& b : c->histogram_rows(s)) {
                 py::dict bd;
                 for (std::size_t k = 0; k < hist.size() && k < b.size(); ++k) bd[py::str(hist[k])] = b[k];
                 bins.append(bd);
               }
               d["histogram"] = bins;
               samples.append(d);
             }
             return py::dict("report"_a = c->report(), "samples"_a = samples);
           })
      .def("dem_rebuild",
           [](PyRun& r) {
             require(r, PyModel::dem);
             dem_simulation(r.model()).rebuild_neighbors();
           })
      .def("dem_label_names",
           [](PyRun& r) {
             require(r, PyModel::dem);
             return dem_simulation(r.model()).particles().label_names;
           })
      // PeriDEM.
      .def("pd_grains",
           [](PyRun& r) {
             require(r, PyModel::peridem);
             PeridemSimulation& sim = peridem_simulation(r.model());
             sim.refresh_grain_centres();
             const PdGrains& g = std::as_const(sim).grains();
             const std::vector<Vec3> reaction = sim.wall_reactions();
             py::list out;
             for (std::size_t k = 0; k < g.size(); ++k) {
               const bool wall = g.kind[k] == static_cast<int>(PdGrainKind::wall);
               out.append(py::dict("name"_a = sim.grain_names()[k], "kind"_a = wall ? "wall" : "particle",
                                   "nodes"_a = py::make_tuple(g.node_begin[k], g.node_end[k]), "volume"_a = g.volume[k],
                                   "centre"_a = py::make_tuple(g.cx[k], g.cy[k], g.cz[k]),
                                   "velocity"_a = py::make_tuple(g.cvx[k], g.cvy[k], g.cvz[k]),
                                   "reaction"_a = vec(reaction[k])));
             }
             return out;
           })
      .def("pd_touching_pairs",
           [](PyRun& r) {
             require(r, PyModel::peridem);
             return peridem_simulation(r.model()).touching_pairs();
           })
      .def("pd_broken_bonds",
           [](PyRun& r) {
             require(r, PyModel::peridem);
             return peridem_simulation(r.model()).broken_bonds();
           })
      .def("pd_diagnostics",
           [](PyRun& r) {
             require(r, PyModel::peridem);
             PeridemSimulation& sim = peridem_simulation(r.model());
             const PeridemDiagnostics d = sim.diagnostics();
             return py::dict("kinetic_energy"_a = d.kinetic_energy, "bond_energy"_a = d.bond_energy,
                             "contact_energy"_a = d.contact_energy, "max_damage"_a = d.max_damage,
                             "broken_bonds"_a = d.broken_bonds, "contact_pairs"_a = d.contact_pairs,
                             "momentum"_a = vec(d.momentum), "touching_pairs"_a = sim.touching_pairs(),
                             "deepest_penetration"_a = sim.deepest_penetration());
           });
}
