#pragma once
// debris_dem's run as the shared runner sees it: a RunModel over a DemSimulation (thermo columns, dump,
// trajectory and pictures, the health check, stages, the wear analysis and census, checkpoints with the run's own
// state), and the set-up that builds it from the input or a checkpoint. A library, not the executable's
// main, so that other drivers (the Python module, scenarios/python) run a DEM input exactly as debris_dem
// does.
#include "scenarios/common/run/runner.hpp"

namespace debris {

class DemSimulation;
class WearAnalysis;
class SurfaceCensus;

/// Reads the input (or the checkpoint), builds and validates the system and prints what the executable
/// prints before stepping; InputError for bad input, before anything is written.
RunPlan prepare_dem_run(const RunOptions& options);

/// The simulation inside a model that prepare_dem_run() made (std::invalid_argument for any other model):
/// for drivers that read or edit the state between steps.
DemSimulation& dem_simulation(RunModel& model);
/// Its wear analysis, or nullptr when the input has no `wear:`.
const WearAnalysis* dem_wear_analysis(const RunModel& model);
/// Its wear census, or nullptr when the input has no `surfaces:`.
const SurfaceCensus* dem_surface_census(const RunModel& model);

}  // namespace debris
