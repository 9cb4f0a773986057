// debris_dem: runs a cohesive DEM system (Pham-Ba & Molinari) described by one YAML input file on host
// threads (or a GPU in an nvptx build). Writes a thermo CSV, LAMMPS dump frames (OVITO), an HDF5 trajectory
// with an XDMF sidecar (ParaView) and checkpoints to the output directory; `--restart` continues from a
// checkpoint. The run loop, stages included, is the shared runner's (scenarios/common/run/runner.hpp); what a
// DEM run writes and checks is scenarios/common/dem/dem_run. Bad input ends with one message naming the key and the value
// and exit 2, before anything is written; a run whose state turns non-finite or explodes stops with exit 3,
// a message naming the step and the particle, and keeps the last good checkpoint.
#include "scenarios/common/dem/dem_keys.hpp"
#include "scenarios/common/dem/dem_run.hpp"

int main(int argc, char** argv) {
  return debris::run_main(argc, argv, "debris_dem",
                          "debris_dem: cohesive coarse-grained DEM (Pham-Ba & Molinari) on host threads or a GPU",
                          "./build/bin/debris_dem -i scenarios/dem/default.yaml -o out/dem_default",
                          debris::prepare_dem_run, debris::dem_keys(), debris::dem_output_columns(),
                          /*runs_on_ranks=*/true);
}
