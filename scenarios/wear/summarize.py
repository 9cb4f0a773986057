#!/usr/bin/env python3
"""One markdown table row per sheared-junction run, from its output directory and the log of its terminal
output: N, steps, verdict, when the third body was first seen (time and sliding distance), the junction
volume it holds, its centre speed and rolling number, how long in all the run was judged rolling (a
rolling body may be smeared out again later), and the wall time.

    python3 scenarios/wear/summarize.py out/wear/junction_D20_d0_1.5nm[.log] ...

Each argument is a run directory (its <dir>.log beside it holds the terminal output, e.g.
`debris_dem -i case.yaml | tee out/wear/case.log`) or that log; a run named twice (a glob such as
out/wear/junction_* names both) gets one row. The wall time and the rate come from the `total` row of the
pass table debris_dem prints at the end (the last one, if the log holds several runs); without a log they
are '?' (N then comes from the first frame of dump.lammpstrj). A wrong argument (no such directory, no
wear.csv in it) is one line on stderr and exit status 2, before any row is printed.
"""
import csv
import pathlib
import re
import sys

VERDICTS = {0: "ductile", 1: "detached, not rolling", 2: "rolling wear particle"}

# The pass table's last row (scenarios/common/run/runner.cpp):
#   total             12.345   100.0%  3.68 M particle-steps/s while stepping
TOTAL = re.compile(r"^total\s+([0-9.eE+-]+)\s+[0-9.eE+-]+%\s+([0-9.eE+-]+) M particle-steps/s while stepping",
                   re.MULTILINE)


class Wrong(Exception):
    pass


def run_of(arg):
    path = pathlib.Path(arg)
    run = path.with_suffix("") if path.suffix == ".log" else path
    if not run.is_dir():
        raise Wrong(f"no such run directory: {run}" + (f" (for the log {path})" if run != path else ""))
    if not (run / "wear.csv").is_file():
        raise Wrong(f"{run} has no wear.csv (not a debris_dem run with a wear: section?)")
    return run


def particles_in_dump(run):
    """N from the first frame of dump.lammpstrj (None without one)."""
    try:
        with open(run / "dump.lammpstrj") as f:
            head = [f.readline().strip() for _ in range(4)]
        return int(head[3]) if head[2] == "ITEM: NUMBER OF ATOMS" else None
    except (OSError, ValueError, IndexError):
        return None


def summarize(run):
    log = run.with_name(run.name + ".log")
    text = log.read_text(errors="replace") if log.is_file() else ""
    if not text:
        print(f"summarize.py: no log {log}: wall time and rate unknown ('?')", file=sys.stderr)
    with open(run / "wear.csv") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise Wrong(f"{run / 'wear.csv'} has no rows")
    last = rows[-1]
    verdict = int(float(last["verdict"]))
    # The final unbroken stretch of samples with a rigid third body.
    first = None
    for r in reversed(rows):
        if int(float(r["verdict"])) == 0:
            break
        first = r
    rolling = sum(1 for r in rows if int(float(r["verdict"])) == 2)
    dt = (float(rows[-1]["time"]) - float(rows[0]["time"])) / max(1, len(rows) - 1)
    n = re.search(r"particles (\d+), groups", text)
    n = n.group(1) if n else particles_in_dump(run)
    totals = TOTAL.findall(text)
    if len(totals) > 1:
        print(f"summarize.py: {log} holds {len(totals)} pass tables: the wall time is the last one's",
              file=sys.stderr)
    wall, rate = (f"{float(totals[-1][0]):.2f} s", totals[-1][1] + " M") if totals else ("?", "?")
    seen = (f"{float(first['time']) * 1e9:.2f} ns / {float(first['wall_slide']) * 1e9:.0f} nm"
            if first else "-")
    third = (f"{float(last['third_volume']):.2f}, {float(last['centre_speed']):.2f}, "
             f"{float(last['rolling_number']):.2f}, {float(last['residual']):.2f}") if last["third_particles"] != "0" else "-"
    return (f"| {run.name} | {n if n is not None else '?'} | {last['step']} | **{VERDICTS[verdict]}** | {seen} | "
            f"{third} | {rolling * dt * 1e9:.2f} ns | {wall} | {rate} |")


def main(args):
    if not args:
        print("summarize.py: give run directories (or their logs), e.g. out/wear/junction_*", file=sys.stderr)
        return 2
    runs = []
    try:
        for a in args:
            run = run_of(a)
            if run not in runs:
                runs.append(run)
        lines = [summarize(run) for run in runs]
    except Wrong as e:
        print(f"summarize.py: {e}", file=sys.stderr)
        return 2
    print("| case | N | steps | verdict | rigid third body since (time / slide) | last window: junction share, "
          "centre speed, rolling number, fit residual | time judged rolling | wall time | particle-steps/s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for line in lines:
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
