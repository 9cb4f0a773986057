#!/usr/bin/env bash
# The README's MPI section names the executables that refuse to start on several ranks ("... started by
# `mpirun -np N` with N > 1 exit 2 before reading anything"); this MPI build's debris_dem and debris_peridem
# are started on 2 ranks and must do what it says: refuse ('mpirun -np' = 2, exit 2) when named there, and
# go on to read their input otherwise (a missing input file: exit 2 naming the file instead).
#   readme_on_ranks.sh <mpirun> <README.md> <bin dir of the MPI build> <work dir>
set -euo pipefail
mpirun=$1 readme=$2 bin=$3 work=$4
rm -rf "$work" && mkdir -p "$work" && cd "$work"
failed=0
# The sentence, joined onto one line, up to "started by `mpirun -np N`".
sentence=$(sed -n '/^## Beyond one machine (MPI)/,/^## /p' "$readme" | tr '\n' ' ' |
  grep -o '[^.]*started by `mpirun -np N` with N > 1 exit 2 before reading anything' || true)
[ -n "$sentence" ] || { echo "the README's MPI section no longer says which executables refuse ranks: update $0"; exit 1; }
named=$(echo "${sentence%%started by*}" | grep -o '`debris_[a-z_]*`' | tr -d '`')
echo "the README names: $(echo $named)"
for exe in debris_dem debris_peridem; do
  set +e
  OMP_NUM_THREADS=1 "$mpirun" -np 2 --oversubscribe --allow-run-as-root --mca mpi_yield_when_idle 1 \
    "$bin/$exe" -i no_such_input.yaml -o out_$exe > $exe.out 2> $exe.err
  status=$?
  set -e
  [ "$status" = 2 ] || { echo "$exe on 2 ranks: exit $status, not 2"; failed=1; }
  if echo "$named" | grep -qx "$exe"; then
    grep -q "'mpirun -np' = 2" $exe.err && echo "$exe refuses 2 ranks, as the README says" ||
      { echo "the README says $exe refuses ranks, but it runs on them"; cat $exe.err; failed=1; }
  else
    grep -q "'mpirun -np'" $exe.err && { echo "$exe refuses ranks, but the README says nothing of it"; cat $exe.err; failed=1; } ||
      echo "$exe runs on 2 ranks (it reads its input), as the README says"
    grep -q "no_such_input.yaml" $exe.err || { echo "$exe on 2 ranks: no message naming the missing input"; cat $exe.err; failed=1; }
  fi
done
exit $failed
