"""Shared pieces of the module's tests: where the repository and the executables are, running an
executable, and an input file as a dict whose relative paths are made absolute (so the same input can be
written anywhere as a YAML file for the executable)."""

import os
import pathlib
import subprocess

import pytest

import debris

REPO = pathlib.Path(__file__).resolve().parents[2]
BIN = pathlib.Path(os.environ.get("DEBRIS_BIN_DIR", REPO / "build" / "bin"))


def run_executable(name, *args, expect=0):
    """Runs build/bin/<name> with args; returns (stdout, stderr). Fails the test on another exit status."""
    p = subprocess.run([str(BIN / name), *map(str, args)], capture_output=True, text=True, timeout=600)
    assert p.returncode == expect, f"{name} {' '.join(map(str, args))}: exit {p.returncode}\n{p.stderr}"
    return p.stdout, p.stderr


def absolute_paths(values, base):
    """The dict with every string that names an existing file or directory under `base` made absolute."""
    if isinstance(values, dict):
        return {k: absolute_paths(v, base) for k, v in values.items()}
    if isinstance(values, list):
        return [absolute_paths(v, base) for v in values]
    if isinstance(values, str) and not os.path.isabs(values) and "/" in values and (base / values).exists():
        return str((base / values).resolve())
    return values


def input_dict(relative, **changes):
    """scenarios/<relative> as a dict with absolute paths; `changes` replace top-level sections' keys:
    input_dict("dem/default.yaml", run={"steps": 3125}) keeps the other keys of `run`."""
    path = REPO / "scenarios" / relative
    values = absolute_paths(debris.load_input(str(path)), path.parent)
    for section, keys in changes.items():
        if isinstance(keys, dict) and isinstance(values.get(section), dict):
            values[section].update(keys)
        else:
            values[section] = keys
    return values


def write_input(values, path):
    """The dict as the YAML file the executable reads (the module's own text for it)."""
    path.write_text(debris.yaml_from_dict(values))
    return path


@pytest.fixture
def repo():
    return REPO
