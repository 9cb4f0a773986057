"""Progress, the pass table and the stages come back as values; stepping releases the GIL; quiet runs print
nothing."""

import re
import threading
import time

import debris
from conftest import input_dict, run_executable, write_input


def test_progress_pass_table_and_stages_are_values(tmp_path, capfd):
    values = input_dict("dem/default.yaml", run={"steps": 2600}, output={"pictures": False, "dump_every": 0})
    sim = debris.Dem(values, output=str(tmp_path), threads=1, quiet=True)
    assert [s["name"] for s in sim.stages] == ["settle", "slide"]
    settle_end = sim.stages[0]["end"]
    assert settle_end == round(0.2e-9 / 80e-15) == sim.stages[1]["start"]  # 0.2 ns of 80 fs steps
    sim.run_stage()
    assert sim.step == settle_end and not sim.done
    p = sim.progress
    assert (p["first_step"], p["step"], p["last_step"]) == (0, settle_end, 2600)
    assert abs(p["fraction"] - settle_end / 2600) < 1e-12 and p["steps_per_second"] > 0
    sim.run()
    assert sim.finished and "verdict" in sim.report.lower()
    t = sim.pass_table()
    names = [r["name"] for r in t["rows"]]
    assert names[0] == "set-up" and names[-2:] == ["output", "rest"] and "contact" in names
    assert abs(sum(r["seconds"] for r in t["rows"]) - t["total"]) < 1e-9 * max(1.0, t["total"])
    assert t["steps"] == 2600 and t["items_steps_per_second"] > 0
    out, err = capfd.readouterr()
    assert out == "" and err == ""  # quiet: the values above are all there is


def test_stepping_releases_the_gil(tmp_path):
    values = input_dict("dem/hcp_wall_load.yaml", output={"dump_every": 0})
    sim = debris.Dem(values, output=str(tmp_path), threads=1, quiet=True)
    ticks, stop, refused = [], threading.Event(), []

    def count():  # a pure-Python loop: it runs only while no other thread holds the GIL
        while not stop.is_set():
            ticks.append(time.perf_counter())
            if len(ticks) % 10000 == 0:
                try:
                    sim.thermo()
                except RuntimeError as e:  # the state is not read while it is stepped
                    refused.append(str(e))

    t = threading.Thread(target=count)
    t.start()
    try:
        start = time.perf_counter()
        sim.run(2000, finish=False)
        end = time.perf_counter()
    finally:
        stop.set()
        t.join()
    assert sim.step == 2000
    during = sum(1 for x in ticks if start < x < end)
    # Held, the GIL would let the loop in only between the run's chunks (a dozen times); released, the loop
    # spins all along (hundreds of thousands of ticks a second).
    assert during > 10000, during
    assert refused and "stepping in another thread" in refused[0]


def _masked(text, directory):
    """The lines of a run's printout with what differs between two runs of one input masked: the pass
    table's seconds, shares and rate, and the output directory."""
    text = text.replace(str(directory), "<output>")
    text = re.sub(r"^(\S+) +[\d.]+ +[\d.]+%", r"\1 <seconds> <share>", text, flags=re.M)
    return re.sub(r"[\d.]+ M particle-steps/s", "<rate> M particle-steps/s", text).splitlines()


def test_loud_run_prints_what_the_executable_prints(tmp_path, capfd):
    # One thread on both sides: the thread tuner's probes depend on the machine's load at the time.
    values = input_dict("dem/hcp_wall_load.yaml", run={"steps": 200}, output={"dump_every": 0})
    out_exe, err_exe = run_executable("debris_dem", "-i", write_input(values, tmp_path / "in.yaml"),
                                      "-o", tmp_path / "exe", "--threads", 1)
    capfd.readouterr()
    debris.Dem(values, output=str(tmp_path / "py"), threads=1).run()
    out, err = capfd.readouterr()
    exe_lines, py_lines = _masked(out_exe, tmp_path / "exe"), _masked(out, tmp_path / "py")
    assert len(exe_lines) > 20 and "pass            seconds   share" in exe_lines
    assert py_lines == exe_lines
    assert err == err_exe


def test_energy_balance_and_wear_census_are_values(tmp_path):
    """sim.energy() is the balance of thermo.csv's last row; sim.surfaces() the census's samples, each with
    its histogram; every particle in exactly one state at every sample."""
    values = input_dict("wear/junction_D10_d0_6nm.yaml", run={"steps": 5000},
                        output={"pictures": False, "dump_every": 0, "thermo_every": 625},
                        surfaces={"window": "0.1 ns"})
    del values["wear"]
    sim = debris.Dem(values, output=str(tmp_path), threads=1, quiet=True)
    sim.run()
    energy = sim.energy()
    assert energy["work_in"] > 0 and energy["work_stages"] == 0
    assert energy["work_in"] == sum(energy["work_drives"].values())
    dissipated = sum(energy[k] for k in ("dissipated_normal", "dissipated_tangential", "dissipated_sliding",
                                         "dissipated_global"))
    closed = (energy["kinetic_energy"] - energy["kinetic_energy_start"] + energy["elastic_energy"]
              - energy["elastic_energy_start"] + dissipated + energy["residual"])
    assert abs(closed - energy["work_in"]) <= 1e-12 * energy["work_in"]
    assert abs(energy["residual"]) < 0.01 * energy["work_in"]
    assert sim.thermo()["work_in"] == energy["work_in"]
    census = sim.surfaces()
    samples = census["samples"]
    assert [s["step"] for s in samples] == list(range(0, 5001, 625))
    n = len(sim.state.id)
    for s in samples:
        assert s["bottom_particles"] + s["top_particles"] + s["third_particles"] == n
        assert sum(b["clusters"] for b in s["histogram"]) == s["clusters"]
