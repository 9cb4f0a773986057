#!/usr/bin/env bash
# What debris_dem says on MPI ranks when the ranks do not fit the box, and when a run stopped during a
# checkpoint left its temporary file behind:
#  - a box of plain numbers (the Table 4 material, no units) too small for 2 ranks: exit 2, one message
#    naming what the user can change (the rank count mpirun starts, the box and its lengths), no unit
#    after a length, nothing written;
#  - checkpoint.h5.tmp beside a finished checkpoint (what a kill while the next one was written leaves; here
#    its first bytes, as a cut-off write leaves them): the run continuing there on 2 ranks removes it and
#    says so once; a fresh run into a directory whose only checkpoint was cut off, on 2 ranks and in the
#    serial build, too.
#   messages_on_ranks.sh <mpirun> <debris_dem> <serial build's debris_dem> <work dir>
set -euo pipefail
mpirun=$1 exe=$2 serial=$3 work=$4
source "$(dirname "$0")/on_ranks.sh"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive

# An fcc block of 3 x 3 x 3 cells, 100 apart (box edge 3 x 100 sqrt 2 = 424.26), periodic: the pair cutoff
# + skin of particles of diameter 100 exceeds 424.26 / 4, so each axis takes one subdomain only.
input() {  # input <cells> <steps> <output directory>
  cat <<EOF
material:
  youngs_modulus: 1
  poisson_ratio: 0.15
  tensile_strength: 0.2
  shear_strength: 0.1
  surface_energy: 1.5
  restitution: 0.95
  density: 1
particles:
  lattice: {kind: fcc, spacing: 100, diameter: 100, cells: $1}
box:
  periodic: [true, true, true]
run:
  steps: $2
  time_step_fraction: 0.1
output:
  directory: $3
  thermo_every: 10
  checkpoint_every: 20
EOF
}

input "[3, 3, 3]" 20 small > small.yaml
set +e
run 2 -i small.yaml > small.out 2> small.err
status=$?
set -e
[ "$status" = 2 ] || { echo "a box too small for 2 ranks: exit $status, not 2"; failed=1; }
message=$(grep "input error" small.err || true)
edge="424.26[0-9]*"
want="input error: 'mpirun -np' = 2: no grid of 2 ranks fits this box: this box, $edge x $edge x $edge, takes at most"
want="$want 1 along x, 1 along y and 1 along z (1 rank in all)"
[ "$(grep -c "input error" small.err)" = 1 ] || { echo "a box too small for 2 ranks: not one message"; failed=1; }
grep -q "$want" small.err || { echo "a box too small for 2 ranks: no message naming mpirun -np and the box"; failed=1; }
grep -q "start at most 1 rank (mpirun -np 1), or make the box larger" small.err ||
  { echo "a box too small for 2 ranks: the message does not say what to change"; failed=1; }
# A run of plain numbers has no unit: none after the ghost width (2 x <width>:), nor any 'm' after a number.
grep -q "(2 x [0-9][0-9.e+-]*: the pair cutoff + skin" small.err || { echo "no unitless ghost width"; failed=1; }
if grep -q "[0-9] m\b" small.err; then echo "a length in metres in a run without units"; failed=1; fi
grep -q "run\.ranks" small.err && { echo "the message names run.ranks, which no input has"; failed=1; }
[ ! -e small/thermo.csv ] || { echo "a box too small for 2 ranks wrote thermo.csv"; failed=1; }
echo "message: $message"

# 6 cells along x (848.5 long): 2 ranks fit. A checkpoint at step 20, then a stale checkpoint.h5.tmp beside it.
input "[6, 3, 3]" 20 stale > first.yaml
input "[6, 3, 3]" 40 stale > longer.yaml
run 2 -i first.yaml > first.log
[ -e stale/checkpoint.h5 ] || { echo "no checkpoint written"; exit 1; }
head -c 4096 stale/checkpoint.h5 > stale/checkpoint.h5.tmp
run 2 -i longer.yaml --restart stale/checkpoint.h5 > continued.log
said="removed stale/checkpoint.h5.tmp, a checkpoint left unfinished by a run stopped while writing it"
[ "$(grep -c "^$said (checkpoint.h5 beside it is the last one finished)" continued.log)" = 1 ] ||
  { echo "the continued run on 2 ranks did not say once that it removed checkpoint.h5.tmp"; cat continued.log; failed=1; }
[ ! -e stale/checkpoint.h5.tmp ] || { echo "checkpoint.h5.tmp is still there"; failed=1; }
[ "$(tail -1 stale/thermo.csv | cut -d, -f1)" = 40 ] || { echo "the continued run did not reach step 40"; failed=1; }
# Only the cut-off one: a fresh run on 2 ranks, and one of the serial build.
for how in 2 serial; do
  rm -f stale/checkpoint.h5
  head -c 4096 /dev/zero > stale/checkpoint.h5.tmp
  run $how -i first.yaml > fresh_$how.log
  [ "$(grep -c "^$said (no checkpoint was finished there)" fresh_$how.log)" = 1 ] ||
    { echo "a fresh run ($how) did not say once that it removed checkpoint.h5.tmp"; cat fresh_$how.log; failed=1; }
  [ ! -e stale/checkpoint.h5.tmp ] && [ -e stale/checkpoint.h5 ] ||
    { echo "a fresh run ($how): checkpoint.h5.tmp left, or no checkpoint.h5"; failed=1; }
done
[ $failed = 0 ] && echo "all as expected"
exit $failed
