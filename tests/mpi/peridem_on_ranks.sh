#!/usr/bin/env bash
# debris_peridem cut among MPI ranks writes what the serial build writes: thermo.csv byte for byte, the HDF5
# node trajectory and the final checkpoint dataset for dataset (h5diff, from hdf5-tools), on
#  - compression_small.yaml (five grains in a box of four walls under gravity: a settle with a global
#    damping, then the lid placed and pressed down until the grains split; walls crossing every cut, placed
#    and moving) on 1 to 4 ranks;
#  - compressive_small.yaml (15 grains of 8 shapes, concave ones among them, in a container closed by a
#    moving lid) on 1 to 4 ranks;
#  - a two-grain impact that breaks bonds (fracture_m1.yaml with the top grain 1 mm higher and a plate far
#    below, so that the box can be cut in four) on 1 to 4 ranks, and without the plate on 3 ranks the named
#    error of grains too large for the ranks;
#  - eight spheres in 3D over a rising floor (peridem_spheres_3d.yaml) on 1 to 4 ranks;
#  - 1,000 steps of the 502-grain deck (compressive_n500.yaml, 62,994 nodes) on 1 to 4 ranks.
# Checkpoints continue across rank counts: one written on 4 ranks continues on 2, one the serial build wrote
# on 3, to the same thermo.csv and final checkpoint. Bad input on 3 ranks: one message, exit 2, nothing
# written. A run that blows up: the same health-check stop in the serial build and on 1 and 3 ranks. About 2
# minutes on 2 cores.
#   peridem_on_ranks.sh <mpirun> <debris_peridem> <serial build's debris_peridem> <source dir> <work dir>
set -euo pipefail
mpirun=$1 exe=$2 serial=$3 src=$4 work=$5
source "$(dirname "$0")/on_ranks.sh"
decks=$src/scenarios/peridem
rm -rf "$work" && mkdir -p "$work" && cd "$work"
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive
check() {  # check <deck> <what> <rank counts...>: the serial build's files again on each count
  local deck=$1 what=$2
  shift 2
  run serial -i "$deck.yaml" -o "$deck.serial" > "$deck.serial.log"
  for np in "$@"; do
    run "$np" -i "$deck.yaml" -o "$deck.$np" > "$deck.$np.log"
    same "$deck.serial/thermo.csv" "$deck.$np/thermo.csv" "$what: thermo.csv on $np ranks"
    same_h5 "$deck.serial/trajectory.h5" "$deck.$np/trajectory.h5" "$what: trajectory.h5 on $np ranks"
    same_h5 "$deck.serial/checkpoint.h5" "$deck.$np/checkpoint.h5" "$what: checkpoint.h5 on $np ranks"
    [ "$np" = 1 ] || grep -q "^comm " "$deck.$np.log" || { echo "$what: no comm row on $np ranks"; failed=1; }
  done
}
edit() {  # edit <input> <output> <sed expressions...>: each must change the file (else the deck changed)
  local in=$1 out=$2
  shift 2
  cp "$in" "$out"
  for e in "$@"; do
    cp "$out" "$out.before"
    sed -i -e "$e" "$out"
    cmp -s "$out" "$out.before" && { echo "$in changed ('$e' no longer applies): update $0"; exit 1; }
  done
  rm -f "$out.before"
}

# compression_small: thermo every 100 steps, frames every 3,000, checkpoints every 6,000 (18,000 steps), and
# a global damping in the settle that the press ends.
edit "$decks/compression_small.yaml" compression.yaml \
  's|trajectory_every: 1000|trajectory_every: 3000\n  checkpoint_every: 6000|' \
  's|{name: settle, duration: 0.2 ms}|{name: settle, duration: 0.2 ms, global_damping: 500 s^-1}|' \
  's|duration: 1.6 ms|duration: 1.6 ms\n    global_damping: 0 s^-1|'
check compression "compression_small" 1 2 3 4
last=$(tail -1 compression.serial/thermo.csv | cut -d, -f7)
grep -q "broken_bonds" compression.serial/thermo.csv && [ "$last" -gt 0 ] ||
  { echo "compression_small: no bond broke"; failed=1; }

edit "$decks/compressive_small.yaml" compressive.yaml "s|file: data/|file: $decks/data/|"
check compressive "compressive_small" 1 2 3 4

# The two-grain impact: 4,500 steps. Its box takes 2 ranks along y; a plate far below (never reached) makes
# it tall enough for 4, and then 82 bonds break (the plate's mesh sets h of eq 35, so R_c and K_n).
edit "$decks/fracture_m1.yaml" pair.yaml 's|centre: \[0, 3 mm, 0\]|centre: [0, 4 mm, 0]|' \
  's|final_time: 0.6 ms|final_time: 0.9 ms|' 's|trajectory_every: 100|trajectory_every: 1500\n  checkpoint_every: 1500|'
edit pair.yaml impact.yaml \
  's|^shapes:|shapes:\n  plate: {type: rectangle, lo: [-3 mm, -7.5 mm, 0], hi: [3 mm, -7 mm, 0], mesh_size: 0.2 mm}|' \
  's|^contact:|walls:\n  - {name: plate, shape: plate, material: M1}\ncontact:|'
check impact "two-grain impact" 1 2 3 4
[ "$(tail -1 impact.serial/thermo.csv | cut -d, -f7)" -gt 0 ] || { echo "two-grain impact: no bond broke"; failed=1; }
# Without the plate, 3 ranks are too many: a named error, exit 2, no run output.
set +e
run 3 -i pair.yaml -o pair.3 > pair.3.out 2> pair.3.err
status=$?
set -e
[ "$status" = 2 ] || { echo "two grains on 3 ranks: exit $status, not 2"; failed=1; }
grep -q "input error: 'mpirun -np' = 3: .*(2 ranks in all).*(mpirun -np 2)" pair.3.err ||
  { echo "two grains on 3 ranks: no message naming mpirun -np and 2 ranks"; cat pair.3.err; failed=1; }
# (Only the meshes of the input's shapes, a cache the input's reading keeps in <output>/meshes.)
[ ! -e pair.3/thermo.csv ] && [ ! -e pair.3/checkpoint.h5 ] || { echo "two grains on 3 ranks wrote run output"; failed=1; }

# 3D: eight spheres collide over a rising floor (tests/mpi/peridem_spheres_3d.yaml).
cp "$src/tests/mpi/peridem_spheres_3d.yaml" spheres.yaml
check spheres "3D spheres" 1 2 3 4

# 1,000 steps of the 502-grain deck, thermo every 100, frames every 500.
edit "$decks/compressive_n500.yaml" n500.yaml "s|file: data/|file: $decks/data/|" 's|steps: 100$|steps: 1000|' \
  's|thermo_every: 10 |thermo_every: 100 |' 's|trajectory_every: 100 |trajectory_every: 500 |'
check n500 "502 grains" 1 2 3 4

# Restarts across rank counts: 4 -> 2, and the serial build's checkpoint on 3, from step 9,000 of
# compression_small.
edit compression.yaml half.yaml 's|^run:|run:\n  steps: 9000|'
run 4 -i half.yaml -o from4 > from4.log
run 2 -i compression.yaml --restart from4/checkpoint.h5 > to2.log
run serial -i half.yaml -o from1 > from1.log
run 3 -i compression.yaml --restart from1/checkpoint.h5 > to3.log
ref=compression.serial
same $ref/thermo.csv from4/thermo.csv "thermo.csv written on 4 ranks to step 9000, continued on 2"
same_h5 $ref/checkpoint.h5 from4/checkpoint.h5 "checkpoint.h5 written on 4 ranks to step 9000, continued on 2"
same $ref/thermo.csv from1/thermo.csv "thermo.csv written serially to step 9000, continued on 3 ranks"
same_h5 $ref/checkpoint.h5 from1/checkpoint.h5 "checkpoint.h5 written serially to step 9000, continued on 3 ranks"

# Bad input: rank 0 alone says so, every rank exits 2, nothing is written.
edit compression.yaml bad.yaml 's|bulk_modulus: 0.0216 GPa|bulk_modulus: -0.0216 GPa|'
set +e
run 3 -i bad.yaml -o bad > bad.out 2> bad.err
status=$?
set -e
[ "$status" = 2 ] || { echo "bad input on 3 ranks: exit $status, not 2"; failed=1; }
[ "$(grep -c "input error: .*bulk_modulus' = " bad.err)" = 1 ] || { echo "bad input: not one message"; cat bad.err; failed=1; }
[ ! -e bad ] || { echo "bad input wrote bad/"; failed=1; }

# A run that blows up (30 times the stable time step): the same health-check stop in the serial build and on
# 1 and 3 ranks, exit 3.
edit compression.yaml unstable.yaml 's|time_step: 0.1 us|time_step: 5 us\n  allow_unstable_time_step: true|'
stops_alike unstable.yaml "stopped: " serial 1 3
exit $failed
