// debris_peridem: runs a PeriDEM system (paper B: peridynamic grains that deform and break, in contact with
// each other and with rigid walls) described by one YAML input file (scenarios/common/peridem/peridem_input.hpp).
// Writes a thermo CSV (energies, damage, broken bonds, contacts, wall reactions and, for runs with few
// grains, each grain's centre, velocity and damage), HDF5 + XDMF node frames with damage, grain id and
// velocity (ParaView) and checkpoints to the output directory; `--restart` continues from a checkpoint bit
// for bit. Bad input ends with one message naming the key and the value and exit 2, before anything is
// written; a run whose state turns non-finite or explodes stops with exit 3 and a message naming the step
// and the node, and keeps the last good checkpoint. The run loop, stages included, is the shared runner's
// (scenarios/common/run/runner.hpp); what a PeriDEM run writes and checks is scenarios/common/peridem/peridem_run.
// Under mpirun (an MPI build) the grains are cut among the ranks (peridem_ranks.cpp) and every file is the
// one a single process writes.
#include "scenarios/common/peridem/peridem_keys.hpp"
#include "scenarios/common/peridem/peridem_run.hpp"

int main(int argc, char** argv) {
  return debris::run_main(
      argc, argv, "debris_peridem",
      "debris_peridem: PeriDEM (peridynamic grains with DEM contact, paper B) on host threads or a GPU",
      "./build/bin/debris_peridem -i scenarios/peridem/two_particle.yaml -o out/peridem_two_particle",
      debris::prepare_peridem_run, debris::peridem_keys(), debris::peridem_output_columns(),
      /*runs_on_ranks=*/true);
}
