"""What Python writes is checked as an input is: an edit that writes a value no input could give (a
negative radius, a repeated id, a NaN) raises InputError naming the column, the value and the item, and
leaves the state as it was, so the run goes on as debris_dem runs the unedited input. A dict input's errors
name the key path, not a line of a YAML text the user never saw; run() takes whole step counts within the
plan."""

import filecmp
import re

import numpy as np
import pytest

import debris
from conftest import input_dict, run_executable, write_input


def _hcp(tmp_path):
    return input_dict("dem/hcp_wall_load.yaml", run={"steps": 300},
                      output={"dump_every": 0, "thermo_every": 20, "checkpoint_every": 0,
                              "directory": str(tmp_path / "exe")})


def _free(sim):
    """Indices of two particles of no group (their velocity is not set by a wall's motion)."""
    return np.flatnonzero(np.asarray(sim.state.group) == -1)[:2]


BAD_DEM_EDITS = {  # what is written, and the column and value the error names
    "negative radius": (lambda s, i, j: s.radius.__setitem__(i, -s.radius[i]), "radius", "-"),
    "repeated id": (lambda s, i, j: s.id.__setitem__(i, s.id[j]), "id", None),
    "NaN velocity": (lambda s, i, j: s.vx.__setitem__(i, np.nan), "vx", "nan"),
    "infinite position": (lambda s, i, j: s.y.__setitem__(i, np.inf), "y", "inf"),
    "zero mass": (lambda s, i, j: s.mass.__setitem__(i, 0.0), "mass", "0"),
    "group out of range": (lambda s, i, j: s.group.__setitem__(i, 5), "group", "5"),
}


@pytest.mark.parametrize("case", list(BAD_DEM_EDITS))
def test_a_bad_dem_edit_is_refused_and_the_run_goes_on_unedited(tmp_path, case):
    values = _hcp(tmp_path)
    run_executable("debris_dem", "-i", write_input(values, tmp_path / "in.yaml"))

    sim = debris.Dem(values, output=str(tmp_path / "py"), quiet=True)
    sim.run(100, finish=False)
    before = {c: np.array(getattr(sim.state, c), copy=True) for c in debris.columns("dem")}
    i, j = _free(sim)
    write, column, value = BAD_DEM_EDITS[case]
    if value is None:
        value = str(before["id"][j])
    with pytest.raises(debris.InputError) as e:
        with sim.edit() as state:
            state.vz[j] = 1.0  # a good write beside the bad one: undone with it
            write(state, i, j)
    message = str(e.value)
    assert re.match(rf"input error: 'state\.{column}' = {re.escape(value)}", message), message
    assert f"particle id {before['id'][i]}" in message or f"index {i}" in message, message
    for c, a in before.items():
        assert np.array_equal(np.asarray(getattr(sim.state, c)), a, equal_nan=True), c
    sim.run()
    assert filecmp.cmp(tmp_path / "exe" / "thermo.csv", tmp_path / "py" / "thermo.csv", shallow=False)


def test_a_good_dem_edit_still_acts(tmp_path):
    # The checks refuse only what no input could give: a smaller radius is taken, and the run goes on with it.
    values = _hcp(tmp_path)
    sim = debris.Dem(values, output=str(tmp_path / "py"), quiet=True)
    i, _ = _free(sim)
    r = float(sim.state.radius[i])
    with sim.edit() as state:
        state.radius[i] = 0.99 * r
    assert sim.state.radius[i] == 0.99 * r
    sim.run(20, finish=False)
    assert sim.step == 20
    assert 0.99 * r in np.asarray(sim.state.radius)


def test_a_particle_grown_past_the_largest_at_set_up_is_refused(tmp_path):
    # The neighbour search's reach is fixed at set-up for its largest pair: a grown particle would lose pairs
    # (and the list's next build would stop the run). Refused at the edit, with positions written too (whose
    # rebuild re-sorts the columns), and the run goes on unedited.
    sim = debris.Dem(_hcp(tmp_path), output=str(tmp_path / "py"), quiet=True)
    i, _ = _free(sim)
    r = float(np.asarray(sim.state.radius).max())
    for with_positions in (False, True):
        with pytest.raises(debris.InputError, match=r"'state\.radius' = .*larger than the largest particle at set-up"):
            with sim.edit() as state:
                state.radius[i] = 1.01 * r
                if with_positions:
                    state.x[i] = state.x[i]
        assert float(np.asarray(sim.state.radius).max()) == r
    sim.run(20, finish=False)
    assert sim.step == 20


def test_a_lighter_particle_is_checked_against_the_time_step(tmp_path):
    # dt = 0.1 dt_c (eq 6, dt_c = sqrt(2 m / k_N) for the pair of two such particles): a mass 1/200 of the
    # lightest puts dt_c at 0.1 / sqrt(200) of what it was, below dt.
    sim = debris.Dem(_hcp(tmp_path), output=str(tmp_path / "py"), quiet=True)
    i, _ = _free(sim)
    m = float(np.asarray(sim.state.mass).min())
    with pytest.raises(debris.InputError, match=r"'state\.mass' = .*critical time step"):
        with sim.edit() as state:
            state.mass[i] = m / 200
    assert sim.state.mass[i] != m / 200


BAD_PERIDEM_EDITS = {
    "negative volume": (lambda s, i: s.volume.__setitem__(i, -1e-9), "volume", "-1e-09"),
    "NaN velocity": (lambda s, i: s.vy.__setitem__(i, np.nan), "vy", "nan"),
    "repeated id": (lambda s, i: s.id.__setitem__(i, s.id[i + 1]), "id", None),
    "node moved to another grain": (lambda s, i: s.grain.__setitem__(i, s.grain[i] + 1), "grain", None),
}


@pytest.mark.parametrize("case", list(BAD_PERIDEM_EDITS))
def test_a_bad_peridem_edit_is_refused_and_the_run_goes_on_unedited(tmp_path, case):
    values = input_dict("peridem/compressive_small.yaml", run={"steps": 60},
                        output={"thermo_every": 10, "trajectory_every": 0, "checkpoint_every": 0,
                                "directory": str(tmp_path / "exe")})
    run_executable("debris_peridem", "-i", write_input(values, tmp_path / "in.yaml"))
    sim = debris.Peridem(values, output=str(tmp_path / "py"), quiet=True)
    sim.run(30, finish=False)
    before = {c: np.array(getattr(sim.state, c), copy=True) for c in debris.columns("peridem")}
    write, column, value = BAD_PERIDEM_EDITS[case]
    with pytest.raises(debris.InputError, match=rf"^input error: 'state\.{column}' = "
                                                 rf"{re.escape(value) if value else ''}.*node id"):
        with sim.edit() as state:
            write(state, 5)
    for c, a in before.items():
        assert np.array_equal(np.asarray(getattr(sim.state, c)), a, equal_nan=True), c
    sim.run()
    assert filecmp.cmp(tmp_path / "exe" / "thermo.csv", tmp_path / "py" / "thermo.csv", shallow=False)


def test_dict_input_errors_name_the_key_path_not_a_line(tmp_path):
    # Errors the reader places on a line of the file: the executable names the file's line; from a dict the
    # message is the same, without a line of the YAML text the dict was made into.
    density = input_dict("dem/hcp_wall_load.yaml")
    density["material"]["density"] = "abc"
    typo = input_dict("dem/hcp_wall_load.yaml")
    typo["run"]["stepz"] = 10
    for values, key in ((density, "material.density"), (typo, "run.stepz")):
        values["output"]["directory"] = str(tmp_path / "out")
        path = write_input(values, tmp_path / "bad.yaml")
        _, err = run_executable("debris_dem", "-i", path, expect=2)
        line = err.strip().splitlines()[-1]
        assert re.search(rf"\({re.escape(str(path))} line \d+\)$", line) and f"'{key}'" in line, line
        with pytest.raises(debris.InputError) as e:
            debris.Dem(values, output=str(tmp_path / "py"), quiet=True)
        assert str(e.value) == re.sub(r" \([^()]* line \d+\)$", "", line[len("debris_dem: "):])
        assert " line " not in str(e.value)


def test_run_takes_whole_step_counts_within_the_plan(tmp_path):
    sim = debris.Dem(_hcp(tmp_path), output=str(tmp_path / "py"), quiet=True)
    assert sim.last_step == 300
    with pytest.raises(TypeError, match=r"run\(steps=1\.5\).*whole number"):
        sim.run(1.5)
    with pytest.raises(TypeError, match=r"run\(steps=True\)"):
        sim.run(True)
    with pytest.raises(ValueError, match=r"run\(steps=1000000000000\) at step 0: the plan ends at step 300"):
        sim.run(10**12)
    with pytest.raises(ValueError, match=r"run\(steps=-1\)"):
        sim.run(-1)
    assert sim.step == 0
    sim.run(np.int64(120), finish=False)  # numpy integers are whole numbers
    assert sim.step == 120
    with pytest.raises(ValueError, match="180 steps from here"):
        sim.run(181)
    sim.run(180)
    assert sim.step == 300 and sim.finished
