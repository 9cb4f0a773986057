"""A run driven from Python writes what the executable writes, bit for bit: thermo.csv (and the wear
analysis's wear.csv) on the default DEM input (the sheared junction, cut to 3,125 steps: the settling
stage, its end and the start of the slide) and on compressive_small.yaml (300 steps), from the input file,
from a dict of the same keys, and stepped in uneven chunks."""

import filecmp

import debris
from conftest import input_dict, run_executable, write_input


def _compare(tmp_path, exe, model, values, chunks, files):
    yaml_file = write_input(dict(values, output=dict(values["output"], directory=str(tmp_path / "exe"))),
                            tmp_path / "input.yaml")
    run_executable(exe, "-i", yaml_file)
    runs = {
        "file": lambda out: model(str(yaml_file), output=out, quiet=True),
        "dict": lambda out: model(values, output=out, quiet=True),
    }
    for how, make in runs.items():
        out = tmp_path / how
        sim = make(str(out))
        for n in chunks:
            sim.run(n)
        sim.run()
        assert sim.done and sim.finished
        for f in files:
            assert filecmp.cmp(tmp_path / "exe" / f, out / f, shallow=False), f"{how}: {f} differs"


def test_default_dem_input_thermo_is_the_executables(tmp_path):
    values = input_dict("dem/default.yaml", run={"steps": 3125},
                        output={"pictures": False, "dump_every": 0, "checkpoint_every": 0, "thermo_every": 125})
    _compare(tmp_path, "debris_dem", debris.Dem, values, [1, 7, 600, 1], ["thermo.csv", "wear.csv"])


def test_compressive_small_thermo_is_the_executables(tmp_path):
    values = input_dict("peridem/compressive_small.yaml", run={"steps": 300},
                        output={"thermo_every": 20, "trajectory_every": 0, "checkpoint_every": 0})
    _compare(tmp_path, "debris_peridem", debris.Peridem, values, [3, 50, 1], ["thermo.csv"])


def test_dict_input_is_the_file_read_back(repo, tmp_path):
    # load_input and yaml_from_dict are inverse on the shipped inputs: the same keys, the same values.
    for relative in ["dem/default.yaml", "dem/hcp_wall_load.yaml", "peridem/compressive_small.yaml",
                     "restitution/tables.yaml"]:
        values = debris.load_input(str(repo / "scenarios" / relative))
        again = debris.load_input(str(write_input(values, tmp_path / "again.yaml")))
        assert again == values, relative
    values = debris.load_input(str(repo / "scenarios/dem/default.yaml"))
    assert values["material"]["youngs_modulus"] == "73 GPa"
    assert values["run"]["threads"] == 1 and values["output"]["pictures"] is True
    assert values["wear"]["moving"] == [0.1, 0.9]
    assert values["groups"][1]["velocity"] == [0, "free", 0]
