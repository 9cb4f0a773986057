"""Errors are Python exceptions with the executables' messages, and checkpoints cross between the module
and the executables both ways, bit for bit."""

import filecmp
import shutil

import pytest

import debris
from conftest import input_dict, run_executable, write_input


def _bad_inputs():
    nu = input_dict("dem/hcp_wall_load.yaml", material={"poisson_ratio": 0.3})
    radius = input_dict("dem/hcp_wall_load.yaml")
    radius["particles"]["lattice"]["diameter"] = -100
    missing = input_dict("dem/default.yaml")
    missing["particles"]["lammps_data"] = "/nonexistent/silica.data"
    step = input_dict("peridem/compressive_small.yaml", run={"time_step": "1 ms"})
    rigid = input_dict("dem/hcp_wall_load.yaml")
    rigid["stages"] = [{"name": "kick", "steps": 10, "groups": [{"name": "top", "motion": "velocity",
                                                                 "velocity": [1, 0, 0], "set_velocity": [1, 0, 0]}]}]
    return {"nu above 0.25": ("debris_dem", debris.Dem, nu, "material.poisson_ratio"),
            "negative diameter": ("debris_dem", debris.Dem, radius, "particles.lattice.diameter"),
            "missing data file": ("debris_dem", debris.Dem, missing, "/nonexistent/silica.data"),
            "time step over the stable one": ("debris_peridem", debris.Peridem, step, "run.time_step"),
            "set_velocity on a rigid group": ("debris_dem", debris.Dem, rigid, "stages[0].groups[0].set_velocity")}


@pytest.mark.parametrize("case", list(_bad_inputs()))
def test_bad_input_raises_the_executables_message(tmp_path, case):
    exe, model, values, key = _bad_inputs()[case]
    values["output"]["directory"] = str(tmp_path / "out")
    _, err = run_executable(exe, "-i", write_input(values, tmp_path / "bad.yaml"), expect=2)
    line = err.strip().splitlines()[-1]
    assert line.startswith(exe + ": input error: ") and key in line
    with pytest.raises(debris.InputError) as e:
        model(values, output=str(tmp_path / "py"), quiet=True)
    assert isinstance(e.value, ValueError)
    assert str(e.value) == line[len(exe) + 2:]
    assert not (tmp_path / "out").exists() and not (tmp_path / "py").exists()  # nothing written


def test_bad_arguments_and_missing_files():
    with pytest.raises(ValueError, match="give an input"):
        debris.Dem()
    with pytest.raises(debris.InputError, match="nonexistent.yaml"):
        debris.Dem("/nonexistent.yaml")
    with pytest.raises(debris.InputError, match="restart"):
        debris.Dem(restart="/nonexistent/checkpoint.h5")
    with pytest.raises(TypeError, match="material.density"):
        debris.Dem({"material": {"density": object()}})
    with pytest.raises(ValueError, match="threads"):
        debris.Dem("/nonexistent.yaml", threads=-1)


def test_a_stopped_run_names_the_step_and_the_last_good_checkpoint(tmp_path):
    # A time step far over the stable one, insisted on: the run blows up and the health check stops it.
    values = input_dict("dem/hcp_wall_load.yaml",
                        run={"time_step_fraction": 3.0, "allow_unstable_time_step": True, "global_damping": 0,
                             "steps": 4000},
                        output={"checkpoint_every": 200, "directory": str(tmp_path / "exe")})
    _, err = run_executable("debris_dem", "-i", write_input(values, tmp_path / "blow.yaml"), expect=3)
    stopped = [l for l in err.splitlines() if "stopped:" in l][-1]
    last_good = [l for l in err.splitlines() if "last good checkpoint" in l][-1]
    sim = debris.Dem(values, output=str(tmp_path / "py"), quiet=True)
    with pytest.raises(debris.RunStopped) as e:
        sim.run()
    message = str(e.value)
    assert message.startswith(stopped.split("stopped: ", 1)[1])
    assert last_good.split("checkpoint is ", 1)[1].replace(str(tmp_path / "exe"), str(tmp_path / "py")) in message
    with pytest.raises(debris.RunStopped, match="stopped earlier"):
        sim.run(1)


def _restart_case(tmp_path):
    return input_dict("dem/default.yaml", run={"steps": 2500},
                      output={"pictures": False, "dump_every": 0, "checkpoint_every": 0, "thermo_every": 125})


def test_a_checkpoint_from_python_restarts_in_the_executable(tmp_path):
    values = _restart_case(tmp_path)
    whole = tmp_path / "whole"
    run_executable("debris_dem", "-i", write_input(values, tmp_path / "in.yaml"), "-o", whole)

    sim = debris.Dem(values, output=str(tmp_path / "py"), quiet=True)
    sim.run(1250, finish=False)
    path = sim.checkpoint()
    assert path == str(tmp_path / "py" / "checkpoint.h5")
    del sim
    run_executable("debris_dem", "--restart", path, "-i", tmp_path / "in.yaml")
    for f in ("thermo.csv", "wear.csv"):
        assert filecmp.cmp(whole / f, tmp_path / "py" / f, shallow=False), f


def test_a_checkpoint_from_the_executable_restarts_in_python(tmp_path):
    values = _restart_case(tmp_path)
    whole = tmp_path / "whole"
    run_executable("debris_dem", "-i", write_input(values, tmp_path / "in.yaml"), "-o", whole)
    half = dict(values, run=dict(values["run"], steps=1250))
    part = tmp_path / "part"
    run_executable("debris_dem", "-i", write_input(half, tmp_path / "half.yaml"), "-o", part)

    sim = debris.Dem(values, restart=str(part / "checkpoint.h5"), quiet=True)
    assert sim.step == 1250 and sim.directory == str(part)
    sim.run()
    for f in ("thermo.csv", "wear.csv"):
        assert filecmp.cmp(whole / f, part / f, shallow=False), f
    # Only the input the checkpoint keeps: the restart runs from it alone (the executable's --restart alone).
    again = tmp_path / "again"
    shutil.copytree(part, again)
    sim = debris.Dem(restart=str(again / "checkpoint.h5"), quiet=True)
    assert sim.step == 2500 and sim.done
    sim.run()
    assert sim.finished and sim.thermo()["step"] == 2500
