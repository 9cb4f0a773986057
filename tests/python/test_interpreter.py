"""`import debris` under another Python than the one it was built for (a pyenv or conda python3 first on
PATH) says which interpreter it was built for and the command that runs it there, instead of a bare
ModuleNotFoundError for numpy or an error loading the compiled part."""

import os
import re
import shutil
import subprocess
import sys

import pytest

import debris

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(debris.__file__)))


def _other_interpreters():
    """Every python3 on PATH that is not the interpreter running these tests (a pyenv shim is asked which
    interpreter it runs)."""
    mine = os.path.realpath(sys.executable)
    found = {}
    for d in os.environ.get("PATH", "").split(os.pathsep):
        path = os.path.join(d, "python3")
        if not os.access(path, os.X_OK) or os.path.realpath(path) == mine:
            continue
        p = subprocess.run([path, "-c", "import sys; print(sys.executable)"], capture_output=True, text=True,
                           timeout=60)
        real = os.path.realpath(p.stdout.strip()) if p.returncode == 0 else ""
        if real and real != mine:
            found.setdefault(real, path)
    return list(found.values())


def test_another_interpreter_is_told_which_one_debris_was_built_for():
    others = _other_interpreters()
    if not others:
        pytest.skip(f"no python3 on PATH other than {sys.executable}: nothing to import debris with wrongly")
    env = dict(os.environ, PYTHONPATH=PACKAGE_DIR)
    refused = 0
    for python in others:
        p = subprocess.run([python, "-c", "import debris"], capture_output=True, text=True, env=env, timeout=120,
                           cwd=os.path.dirname(PACKAGE_DIR))
        if p.returncode == 0:
            continue  # an interpreter debris works with (the same Python with numpy): nothing to say
        refused += 1
        last = p.stderr.strip().splitlines()[-1]
        assert last.startswith("ImportError: debris: "), (python, p.stderr)
        built = re.search(r"built for (\S+) \(Python ([\d.]+)\)", last)
        assert built, last
        # The interpreter these tests run under imports debris: it is the one named.
        assert os.path.realpath(built.group(1)) == os.path.realpath(sys.executable), last
        assert built.group(2) == sys.version.split()[0], last
        command = f"PYTHONPATH={PACKAGE_DIR} {built.group(1)} "
        assert command in last, last
    if refused == 0:
        pytest.skip(f"every other python3 on PATH ({', '.join(others)}) imports debris")
    # The command the message gives runs.
    p = subprocess.run([built.group(1), "-c", "import debris; print(debris.Dem.__name__)"], capture_output=True,
                       text=True, env=env, timeout=120)
    assert p.returncode == 0 and p.stdout.strip() == "Dem", p.stderr
    assert shutil.which(built.group(1)) or os.path.isabs(built.group(1))
