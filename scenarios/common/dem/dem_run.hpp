#pragma once
// debris_dem's run as the shared runner sees it: a RunModel over a DemSimulation (thermo columns, dump,
// trajectory and pictures, the health check, stages, the wear analysis, checkpoints with the run's own
// state), and the set-up that builds it from the input or a checkpoint. A library, not the executable's
// main, so that other drivers (the Python module of issue 28) run a DEM input exactly as debris_dem does.
#include "scenarios/common/run/runner.hpp"

namespace debris {

/// Reads the input (or the checkpoint), builds and validates the system and prints what the executable
/// prints before stepping; InputError for bad input, before anything is written.
RunPlan prepare_dem_run(const RunOptions& options);

}  // namespace debris
