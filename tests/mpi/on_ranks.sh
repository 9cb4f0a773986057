# What dem_on_ranks.sh and peridem_on_ranks.sh share (sourced, not run): an executable on N ranks and the
# comparisons of its files with one process's. Expects $mpirun, $exe (the MPI build's) and $serial (the same
# executable of the serial build: the reference, so that what the MPI build changes on one rank too shows);
# a difference sets failed=1.
failed=0
[ -x "$serial" ] || {
  echo "no serial build of $(basename "$exe") at '$serial': the files on ranks are compared with the serial" \
    "build's; build it first (cmake -S . -B build && cmake --build build --target $(basename "$exe")), or point" \
    "DEBRIS_SERIAL_BIN_DIR of the MPI build at its bin/"
  exit 1
}
run() {  # run <ranks, or 'serial': the serial build without mpirun> <arguments of the executable...>
  local np=$1
  shift
  if [ "$np" = serial ]; then
    "$serial" "$@"
  else
    "$mpirun" -np "$np" --oversubscribe --allow-run-as-root --mca mpi_yield_when_idle 1 "$exe" "$@"
  fi
}
crossed() {  # crossed <log of a run on ranks> <what>: the pass table's comm row counts particles that crossed a cut
  local n
  n=$(sed -n 's/^comm .*; \([0-9][0-9]*\) particles crossed a cut.*/\1/p' "$1")
  if [ -n "$n" ] && [ "$n" -gt 0 ]; then
    echo "crossed: $n particles, $2"
  else
    echo "NONE crossed a cut: $2 ($1)"
    failed=1
  fi
}
same() {  # same <file a> <file b> <what>
  if cmp -s "$1" "$2"; then echo "same: $3"; else echo "DIFFERS: $3 ($1, $2)"; failed=1; fi
}
same_h5() {  # same_h5 <file a> <file b> <what>: HDF5 files carry their write times, so every dataset instead
  if h5diff "$1" "$2" > /dev/null; then echo "same: $3 (h5diff)"; else echo "DIFFERS: $3 ($1, $2)"; failed=1; fi
}
# stops_alike <input> <pattern of the stop line> <ranks, or serial...>: exit 3 and one stop line, the same on each
stops_alike() {
  local input=$1 pattern=$2 first=
  shift 2
  for np in "$@"; do
    set +e
    run "$np" -i "$input" -o "stopped$np" > "stopped$np.out" 2> "stopped$np.err"
    local status=$?
    set -e
    [ "$status" = 3 ] || { echo "$input on $np ranks: exit $status, not 3"; failed=1; }
    grep "$pattern" "stopped$np.err" > "stopped$np.line" || true
    [ "$(wc -l < "stopped$np.line")" = 1 ] || { echo "$input on $np ranks: not one stop line"; cat "stopped$np.err"; failed=1; }
    if [ -z "$first" ]; then first=stopped$np.line; else same "$first" "stopped$np.line" "the stop of $input on $np ranks"; fi
  done
}
