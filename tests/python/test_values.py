"""Progress, the pass table and the stages come back as values; stepping releases the GIL; quiet runs print
nothing."""

import threading
import time

import debris
from conftest import input_dict


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


def test_loud_run_prints_what_the_executable_prints(tmp_path, capfd):
    values = input_dict("dem/hcp_wall_load.yaml", run={"steps": 200}, output={"dump_every": 0})
    debris.Dem(values, output=str(tmp_path)).run()
    out, _ = capfd.readouterr()
    assert "step" in out and "pass            seconds   share" in out and "output written to" in out
