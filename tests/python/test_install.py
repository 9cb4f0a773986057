"""`cmake --install build --prefix P` puts the package where Python finds it with PYTHONPATH, and it runs
there without the build tree."""

import os
import subprocess
import sys
import sysconfig

from conftest import REPO


def test_installed_module_imports_and_runs(tmp_path):
    build = os.environ.get("DEBRIS_BUILD_DIR", str(REPO / "build"))
    subprocess.run(["cmake", "--install", build, "--prefix", str(tmp_path / "prefix")], check=True,
                   capture_output=True, timeout=300)
    version = sysconfig.get_python_version()
    site = tmp_path / "prefix" / "lib" / f"python{version}" / "site-packages"
    assert (site / "debris" / "__init__.py").exists()
    code = ("import debris, sys; "
            "sim = debris.Dem(sys.argv[1], output=sys.argv[2], quiet=True); sim.run(200); "
            "print(debris.__file__, sim.thermo()['step'])")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    p = subprocess.run([sys.executable, "-c", code, str(REPO / "scenarios/dem/hcp_wall_load.yaml"),
                        str(tmp_path / "out")], capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)
    assert p.returncode == 0, p.stderr
    where, step = p.stdout.split()
    assert where.startswith(str(site)) and int(step) == 200
