"""The two worked examples of scenarios/python/examples, at a reduced size: the junction set-up study
(0.3 ns of slide, two cases, each against debris_dem run on the same input) and the PeriDEM restitution
sweep (two rows of Table 2, full size: they take a second)."""

import csv
import filecmp
import importlib.util
import os
import re
import subprocess
import sys

from conftest import REPO, run_executable, write_input

EXAMPLES = REPO / "scenarios" / "python" / "examples"


def _run(script, *args):
    p = subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)], capture_output=True, text=True,
                       timeout=600, env=dict(os.environ, MPLBACKEND="Agg"))
    assert p.returncode == 0, p.stderr
    return p.stdout


def _example_module(script):
    spec = importlib.util.spec_from_file_location(script.removesuffix(".py"), EXAMPLES / script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_junction_setup_study(tmp_path):
    slide_ns, cases = 0.3, ["baseline", "load_10MPa"]
    out = _run("junction_setup_study.py", "--out", tmp_path / "py", "--slide-ns", slide_ns, "--cases", ",".join(cases))
    lines = {l.split()[0]: l for l in out.splitlines() if l.startswith(tuple(cases))}
    assert list(lines) == cases
    # The same inputs (the script's own case_input) run by debris_dem: its verdict, its wear.csv.
    study = _example_module("junction_setup_study.py")
    for case in cases:
        seed, load, settle = study.CASES[case]
        exe_dir = tmp_path / "exe" / case
        values = study.case_input(seed, load, settle, slide_ns, exe_dir)
        stdout, _ = run_executable("debris_dem", "-i", write_input(values, tmp_path / f"{case}.yaml"), "--threads", 1)
        verdict = re.findall(r"^wear: verdict (\S+) at step", stdout, re.M)[-1]
        shown = re.search(r"settle [\d.]+ ns: (\S+) +mean tangential force +(\S+) nN over the last (\S+) ns.*"
                          r"\((\d+) samples", lines[case])
        assert shown, lines[case]
        assert shown.group(1) == verdict, (case, lines[case], verdict)
        # The printed mean: the executable's wall_force over the last window of its wear.csv.
        with open(exe_dir / "wear.csv") as f:
            rows = list(csv.DictReader(f))
        assert int(shown.group(4)) == len(rows) == 11  # 0.2 ns of settling, 0.3 ns of slide, a sample every 0.05 ns
        span = float(shown.group(3)) * 1e-9
        window = [float(r["wall_force"]) for r in rows if float(r["time"]) >= float(rows[-1]["time"]) - span]
        assert shown.group(2) == f"{sum(window) / len(window) * 1e9:.2f}", (case, lines[case])
        assert filecmp.cmp(exe_dir / "wear.csv", tmp_path / "py" / case / "wear.csv", shallow=False), case
        assert (tmp_path / "py" / case / "checkpoint.h5").exists()
    assert "load  10 MPa" in lines["load_10MPa"]
    png = tmp_path / "py" / "tangential_force.png"
    assert png.stat().st_size > 10000 and png.read_bytes()[:4] == b"\x89PNG"


def test_peridem_restitution_sweep_reproduces_table_2(tmp_path):
    out = _run("peridem_restitution_sweep.py", "--eps", "0.95,0.8", "--out", tmp_path)
    rows = [l.split() for l in out.splitlines()[1:]]
    assert [r[0] for r in rows] == ["0.95", "0.80"]
    for eps, c, paper, steps in rows:
        # Table 2: 0.946 and 0.796; debris_restitution's rows are within 0.005 of the paper (README).
        assert abs(float(c) - float(paper)) < 0.005, (eps, c, paper)
        assert 0 < float(c) < float(eps) + 0.01 and int(steps) > 0
