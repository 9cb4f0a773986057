#!/usr/bin/env python3
"""One markdown table row per sheared-junction run, from its output directory and the log of its terminal
output: N, steps, verdict, when the third body was first seen (time and sliding distance), the junction
volume it holds, its centre speed and rolling number, how long in all the run was judged rolling (a
rolling body may be smeared out again later), and the wall time.

    python3 scenarios/wear/summarize.py out/wear/junction_D20_d0_1.5nm[.log] ...

Each argument is a run directory (its <dir>.log beside it holds the terminal output) or a log.
"""
import csv
import pathlib
import re
import sys

VERDICTS = {0: "ductile", 1: "detached, not rolling", 2: "rolling wear particle"}


def summarize(arg):
    path = pathlib.Path(arg)
    run = path.with_suffix("") if path.suffix == ".log" else path
    log = run.with_name(run.name + ".log")
    text = log.read_text() if log.exists() else ""
    with open(run / "wear.csv") as f:
        rows = list(csv.DictReader(f))
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
    wall = re.search(r"([\d.]+) s wall", text)
    rate = re.search(r"([\d.]+) M particle-steps/s while stepping", text)
    seen = (f"{float(first['time']) * 1e9:.2f} ns / {float(first['wall_slide']) * 1e9:.0f} nm"
            if first else "-")
    third = (f"{float(last['third_volume']):.2f}, {float(last['centre_speed']):.2f}, "
             f"{float(last['rolling_number']):.2f}, {float(last['residual']):.2f}") if last["third_particles"] != "0" else "-"
    return (f"| {run.name} | {n.group(1) if n else '?'} | {last['step']} | **{VERDICTS[verdict]}** | {seen} | "
            f"{third} | {rolling * dt * 1e9:.2f} ns | {wall.group(1) + ' s' if wall else '?'} | "
            f"{rate.group(1) + ' M' if rate else '?'} |")


if __name__ == "__main__":
    print("| case | N | steps | verdict | rigid third body since (time / slide) | last window: junction share, "
          "centre speed, rolling number, fit residual | time judged rolling | wall time | particle-steps/s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for a in sys.argv[1:]:
        print(summarize(a))
