#pragma once
// debris_peridem's run as the shared runner sees it: a RunModel over a PeridemSimulation (thermo columns per
// wall and grain, node frames, the health and penetration checks, stages, checkpoints), and the set-up that
// builds it from the input or a checkpoint. A library, not the executable's main, so that other drivers
// (the Python module, scenarios/python) run a PeriDEM input exactly as debris_peridem does.
#include "scenarios/common/run/runner.hpp"

namespace debris {

class PeridemSimulation;

/// Reads the input (or the checkpoint), builds and validates the system and prints what the executable
/// prints before stepping; InputError for bad input, before anything is written.
RunPlan prepare_peridem_run(const RunOptions& options);

/// The simulation inside a model that prepare_peridem_run() made (std::invalid_argument for any other
/// model): for drivers that read or edit the state between steps.
PeridemSimulation& peridem_simulation(RunModel& model);

}  // namespace debris
