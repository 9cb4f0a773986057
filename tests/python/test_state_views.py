"""The live state as numpy arrays: views read the simulation's memory without copies, writing goes through
an edit that acts as a stage's changes do, and a view made before a re-sort refuses to be read."""

import filecmp

import numpy as np
import pytest

import debris
from conftest import input_dict, write_input


def _hcp_with_probe(set_velocity):
    """The HCP sample under its wall load, with a free group `probe` (the middle layers) that a second
    stage launches sideways (set_velocity) or not."""
    values = input_dict("dem/hcp_wall_load.yaml", run={"steps": -1}, output={"dump_every": 0, "thermo_every": 20})
    del values["run"]["steps"]
    values["groups"].append({"name": "probe", "region": {"y": [500, 700]}, "motion": "free"})
    kick = {"name": "probe", "motion": "free"}
    if set_velocity:
        kick["set_velocity"] = [0.002, 0, -0.001]
    values["stages"] = [{"name": "load", "steps": 200}, {"name": "kick", "steps": 200, "groups": [kick]}]
    return values


def test_velocity_edited_through_a_view_steps_as_the_same_stage_edit(tmp_path):
    staged = debris.Dem(_hcp_with_probe(True), output=str(tmp_path / "stage"), quiet=True)
    staged.run()

    sim = debris.Dem(_hcp_with_probe(False), output=str(tmp_path / "view"), quiet=True)
    sim.run_stage()  # to step 200, where the kick stage starts
    assert sim.step == 200
    index = [g for g in sim.groups].index("probe")
    members = np.asarray(sim.state.group) == index
    assert members.sum() == sim.groups["probe"]["count"] > 0
    with sim.edit() as state:
        state.vx[members] = 0.002
        state.vy[members] = 0.0
        state.vz[members] = -0.001
    assert np.all(np.asarray(sim.state.vx)[members] == 0.002)
    sim.run()
    assert filecmp.cmp(tmp_path / "stage" / "thermo.csv", tmp_path / "view" / "thermo.csv", shallow=False)
    # The edit did work on the system, counted as a stage's would be, and the balance still closes.
    energy = sim.energy()
    assert energy["work_stages"] > 0
    assert energy["work_stages"] == staged.energy()["work_stages"]
    assert abs(energy["residual"]) < 0.01 * energy["work_in"]

    # The kick changes the run: without it the thermo differs.
    plain = debris.Dem(_hcp_with_probe(False), output=str(tmp_path / "plain"), quiet=True).run()
    assert plain.finished
    assert not filecmp.cmp(tmp_path / "stage" / "thermo.csv", tmp_path / "plain" / "thermo.csv", shallow=False)


def test_views_are_the_live_memory_and_read_only(tmp_path):
    sim = debris.Dem(input_dict("dem/hcp_wall_load.yaml"), output=str(tmp_path), quiet=True)
    y = sim.state.y
    a = np.asarray(y)
    assert a.dtype == np.float64 and a.shape == (sim._run.items,)
    assert not a.flags.writeable and not a.flags.owndata  # the simulation's memory, not a copy
    assert np.shares_memory(a, np.asarray(sim.state.y))
    with pytest.raises(ValueError):
        a[0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        y[0] = 1.0
    top = sim.groups["top"]
    before = float(np.mean(y))
    sim.run(10, finish=False)  # the sample's first re-sort comes at step 50
    assert sim._run.generation() == y._generation
    assert float(np.mean(y)) != before  # the same view shows the new state
    ids = np.asarray(sim.state.id)
    assert sorted(ids.tolist()) == list(range(ids.min(), ids.min() + len(ids)))
    assert top["count"] == 200
    assert np.asarray(sim.state.radius).min() > 0
    assert debris.columns("dem")[:3] == ["x", "y", "z"]


def test_a_view_used_after_a_resort_raises(tmp_path):
    sim = debris.Dem(input_dict("dem/hcp_wall_load.yaml"), output=str(tmp_path), quiet=True)
    x, ids = sim.state.x, sim.state.id
    by_id = dict(zip(np.asarray(ids).tolist(), np.asarray(x).tolist()))
    sim.resort()
    for use in (lambda: x[0], lambda: np.asarray(x), lambda: x + 1.0, lambda: len(x), lambda: np.mean(x)):
        with pytest.raises(debris.StaleViewError, match="re-sorted"):
            use()
    # Taken again, the view reads the re-sorted columns: each particle (by id) where it was.
    again = dict(zip(np.asarray(sim.state.id).tolist(), np.asarray(sim.state.x).tolist()))
    assert again == by_id

    # The re-sorts a run makes by itself, at its neighbour rebuilds, do the same.
    y = sim.state.y
    generation = sim.diagnostics()["layout_generation"]
    while sim.diagnostics()["layout_generation"] == generation and not sim.done:
        sim.run(50, finish=False)
    assert sim.diagnostics()["layout_generation"] > generation, "no rebuild in the whole run"
    with pytest.raises(debris.StaleViewError):
        y[0]


def test_a_writable_view_ends_with_its_edit(tmp_path):
    sim = debris.Dem(input_dict("dem/hcp_wall_load.yaml"), output=str(tmp_path), quiet=True)
    with sim.edit() as state:
        vx = state.vx
        vx[0] = vx[0]
        with pytest.raises(RuntimeError, match="edit is open"):
            sim.run(1)
    with pytest.raises(debris.StaleViewError, match="edit that has ended"):
        vx[0] = 1.0


def test_peridem_nodes_damage_and_displacements(tmp_path):
    values = input_dict("peridem/compressive_small.yaml", run={"steps": 200},
                        output={"trajectory_every": 0, "checkpoint_every": 0})
    sim = debris.Peridem(values, output=str(tmp_path), quiet=True)
    sim.run(200, finish=False)
    s = sim.state
    u = sim.displacements()
    assert u.shape == (3, len(s.x))
    assert np.array_equal(u[0], np.asarray(s.x) - np.asarray(s.x0))
    grain = np.asarray(s.grain)
    grains = sim.grains
    names = list(grains)
    for k, (name, g) in enumerate(grains.items()):
        begin, end = g["nodes"]
        assert np.all(grain[begin:end] == k), name
    # The lid moves at -0.06 m/s: its nodes' displacement after 200 steps of 2.5 us is -0.06 * 5e-4 m.
    lid = grains["lid"]["nodes"]
    assert np.allclose(u[1][lid[0]:lid[1]], -0.06 * 200 * 2.5e-6, rtol=1e-9, atol=0)
    damage = np.asarray(s.damage)
    assert np.all((damage >= 0) & np.isfinite(damage))
    assert sim.diagnostics()["max_damage"] == pytest.approx(damage.max(), rel=0, abs=0)
    # Wall reactions equal the thermo row's wall columns.
    row = sim.thermo()
    for wall, f in sim.wall_reactions().items():
        assert f[1] == row[f"{wall}_fy"], wall
    assert "container" in names and "lid" in names
