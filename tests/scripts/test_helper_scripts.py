#!/usr/bin/python3
"""The helper scripts of scenarios/wear, scenarios/rough and scenarios/peridem on small real outputs.

    /usr/bin/python3 tests/scripts/test_helper_scripts.py BUILD/bin      (or DEBRIS_BIN_DIR=BUILD/bin)

Runs, into a temporary directory: a sheared junction (debris_dem with a wear: section, the d0 = 6 nm
sample, 466 particles, 1,750 steps) in two chunks, the second a --restart; and the reduced compression
(debris_peridem, five grains) in two chunks, the first ending before the press starts. Then checks:
summarize.py's wall time is the `total` row of the log; plot.py reads the first dump and the restart's,
dropping the repeated checkpoint frame, and names only what it wrote; compression.py refuses a run too
short for the press and draws damage from a restart chunk's frames; a wrong folder is one line on stderr and
exit status 2 and leaves no folder behind (summarize, plot, compression, damage_picture, settled_pack);
scenarios/patch/plot_sizes.py merges two sizes' cases.csv and counts each panel's points;
scenarios/patch/plot_discretisation.py draws one line per system size and d_l rule, a d0 sweep's rows added.
About 10 s on one core. Needs Debian's python3-matplotlib, python3-numpy and python3-h5py, and gmsh.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
WEAR = SOURCE / "scenarios" / "wear"
PERIDEM = SOURCE / "scenarios" / "peridem"
ROUGH = SOURCE / "scenarios" / "rough"
BIN = None  # set in __main__
WORK = None  # the temporary directory, set in setUpModule

# The D = 20 nm, d0 = 6 nm junction (scenarios/wear/junction_D20_d0_6nm.yaml) shortened: 0.02 ns of
# settling (250 steps) and 0.12 ns of sliding (1,500 steps), the analysis every 25 steps over 0.04 ns,
# a frame every 250 steps, a checkpoint every 500.
WEAR_INPUT = """\
material:
  youngs_modulus: 73 GPa
  poisson_ratio: 0.17
  tensile_strength: 16 GPa
  shear_strength: 9 GPa
  surface_energy: 1.5 N/m
  restitution: 0.9
  density: 2200 kg/m^3
  scaling: 0.5
particles:
  lammps_data: {data}
  masses_from_file: true
box:
  periodic: [true, false, true]
remove:
  difference:
    - {{block: {{y: [15.3133 nm, 25.3133 nm]}}}}
    - {{cylinder: {{axis: y, centre: [30.5462 nm, 0, 20.3577 nm], radius: 10.0000 nm, extent: [15.3133 nm, 25.3133 nm]}}}}
labels:
  - {{name: bottom, region: {{block: {{y: [-inf, 20.3133 nm]}}}}}}
  - {{name: top, region: {{block: {{y: [20.3133 nm, inf]}}}}}}
  - {{name: junction, region: {{cylinder: {{axis: y, centre: [30.5462 nm, 0, 20.3577 nm], radius: 10.0000 nm, extent: [15.3133 nm, 25.3133 nm]}}}}}}
  - {{name: bottom_wall, region: {{block: {{y: [-inf, 9.0000 nm]}}}}}}
  - {{name: top_wall, region: {{block: {{y: [31.6266 nm, inf]}}}}}}
groups:
  - name: bottom_wall
    region: {{block: {{y: [-inf, 9.0000 nm]}}}}
    motion: frozen
  - name: top_wall
    region: {{block: {{y: [31.6266 nm, inf]}}}}
    motion: force
    velocity: [0, free, 0]
    stress: [0, -100 MPa, 0]
stages:
  - name: settle
    duration: 0.02 ns
    global_damping: 0.1
  - name: slide
    duration: 0.12 ns
    global_damping: 0
    groups:
      - {{name: top_wall, motion: force, velocity: [10 m/s, free, 0], stress: [0, -100 MPa, 0]}}
run:
{steps}  time_step: 80 fs
  overlap_limit: auto
  skin: 0.5 nm
  threads: 1
wear:
  every: 25
  bottom_wall: bottom_wall
  top_wall: top_wall
  junction_label: junction
  sliding_axis: x
  normal_axis: y
  window: 0.04 ns
  moving: [0.1, 0.9]
  min_volume_fraction: 0.25
  max_residual: 0.3
  centre_speed: [0.25, 0.75]
  rolling_number: [0.5, 1.5]
  persistence: 0.05 ns
output:
  directory: unused
  thermo_every: 25
  dump_every: 250
  checkpoint_every: 500
"""

# scenarios/peridem/compression_small.yaml shortened: 0.2 ms of settling (2,000 steps), then the lid is
# placed and pressed; a frame every 500 steps.
PERIDEM_INPUT = """\
dimension: 2
materials:
  M1: {{density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 50 J/m^2,
       horizon: 0.6 mm}}
shapes:
  disc: {{type: circle, radius: 1 mm, mesh_size: 0.25 mm}}
  floor: {{type: rectangle, lo: [-4.1 mm, -0.6 mm, 0], hi: [4.1 mm, 0, 0], mesh_size: 0.25 mm}}
  left: {{type: rectangle, lo: [-4.1 mm, 0.25 mm, 0], hi: [-3.5 mm, 8 mm, 0], mesh_size: 0.25 mm}}
  right: {{type: rectangle, lo: [3.5 mm, 0.25 mm, 0], hi: [4.1 mm, 8 mm, 0], mesh_size: 0.25 mm}}
  lid: {{type: rectangle, lo: [-3.2 mm, 9 mm, 0], hi: [3.2 mm, 9.6 mm, 0], mesh_size: 0.25 mm}}
grains:
  - {{name: b1, shape: disc, material: M1, centre: [-2.25 mm, 1.25 mm, 0]}}
  - {{name: b2, shape: disc, material: M1, centre: [0, 1.25 mm, 0]}}
  - {{name: b3, shape: disc, material: M1, centre: [2.25 mm, 1.25 mm, 0]}}
  - {{name: t1, shape: disc, material: M1, centre: [-1.125 mm, 3.1056 mm, 0]}}
  - {{name: t2, shape: disc, material: M1, centre: [1.125 mm, 3.1056 mm, 0]}}
walls:
  - {{name: floor, shape: floor, material: M1}}
  - {{name: left, shape: left, material: M1}}
  - {{name: right, shape: right, material: M1}}
  - {{name: lid, shape: lid, material: M1}}
contact:
  contact_radius_factor: 0.95
  restitution: 0.95
  damping_factor: 100
  friction: 0
  damping: grain_centres
gravity: [0, -10 m/s^2, 0]
stages:
  - {{name: settle, duration: 0.2 ms}}
  - name: press
    duration: 1.6 ms
    walls:
      - {{name: lid, place: {{y_min: 4.26 mm}}, velocity: [0, -0.5 m/s, 0]}}
run:
  steps: {steps}
  time_step: 0.1 us
  threads: 1
output:
  directory: unused
  thermo_every: 100
  trajectory_every: 500
"""

PRESS = ["--press-start", "0.0002", "--time-offset", "0"]  # the lid is placed at run time 0.2 ms


def run(args, **kw):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=120, **kw)


def simulate(exe, args, log=None):
    r = run([BIN / exe] + args + ["--threads", "1"], cwd=WORK)
    if r.returncode != 0:
        raise RuntimeError("%s %s failed (exit %d):\n%s%s" % (exe, " ".join(map(str, args)), r.returncode,
                                                             r.stdout[-3000:], r.stderr[-3000:]))
    if log is not None:
        with open(log, "a") as f:
            f.write(r.stdout)
    return r.stdout


def script(path, *args):
    # compression.py imports damage_picture.py: no __pycache__ left in the source tree.
    return run([sys.executable, path] + list(args), env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1"))


def setUpModule():
    global WORK
    missing = []
    for module, package in (("matplotlib", "python3-matplotlib"), ("numpy", "python3-numpy"), ("h5py", "python3-h5py")):
        try:
            __import__(module)
        except ImportError:
            missing.append(package)
    if missing:
        raise RuntimeError("%s lacks %s: install Debian's %s (cmake/install-debian-deps.sh)"
                           % (sys.executable, ", ".join(missing), " ".join(missing)))
    WORK = pathlib.Path(tempfile.mkdtemp(prefix="debris_helper_scripts_"))
    data = WEAR / "data" / "silica_d0_6nm.data"
    (WORK / "wear_chunk.yaml").write_text(WEAR_INPUT.format(data=data, steps="  steps: 1000\n"))
    (WORK / "wear.yaml").write_text(WEAR_INPUT.format(data=data, steps=""))
    junction = WORK / "junction"
    # The first chunk's terminal output is the log; the restart's goes to a second one (appended to a
    # copy of the first in the test of several pass tables).
    simulate("debris_dem", ["-i", WORK / "wear_chunk.yaml", "-o", junction], log=WORK / "junction.log")
    simulate("debris_dem", ["--restart", junction / "checkpoint.h5", "-i", WORK / "wear.yaml", "-o", junction],
             log=WORK / "restart.log")
    (WORK / "press_chunk.yaml").write_text(PERIDEM_INPUT.format(steps=1500))  # ends before the press
    (WORK / "press.yaml").write_text(PERIDEM_INPUT.format(steps=2600))
    simulate("debris_peridem", ["-i", WORK / "press_chunk.yaml", "-o", WORK / "press_short"])
    shutil.copytree(WORK / "press_short", WORK / "press")
    simulate("debris_peridem", ["--restart", WORK / "press" / "checkpoint.h5", "-i", WORK / "press.yaml",
                                "-o", WORK / "press"])
    # The rough-surface scenario's reduced input (about 1 s), its data file found from here.
    rough = (ROUGH / "rough_small.yaml").read_text().replace("lammps_data: ../wear/data/",
                                                            "lammps_data: %s/" % (WEAR / "data"))
    (WORK / "rough.yaml").write_text(rough)
    simulate("debris_dem", ["-i", WORK / "rough.yaml", "-o", WORK / "rough"])


def tearDownModule():
    if WORK is not None and not os.environ.get("DEBRIS_KEEP_TEST_OUTPUT"):
        shutil.rmtree(WORK, ignore_errors=True)


class Helpers(unittest.TestCase):
    def assertOneLineError(self, r, name, *words):
        """Exit 2, nothing on stdout, one line on stderr that names the script and says what is wrong."""
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertEqual(r.stdout, "")
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, r.stderr)
        self.assertTrue(lines[0].startswith(name + ": "), lines[0])
        self.assertNotIn("Traceback", r.stderr)
        for w in words:
            self.assertIn(w, lines[0])

    def totals(self, log):
        return [float(x) for x in re.findall(r"^total\s+([0-9.]+)\s", log.read_text(), re.MULTILINE)]


class Summarize(Helpers):
    SCRIPT = WEAR / "summarize.py"

    def wall(self, out):
        rows = [line for line in out.splitlines() if line.startswith("| junction ")]
        self.assertEqual(len(rows), 1, out)
        cells = [c.strip() for c in rows[0].strip("|").split("|")]
        self.assertEqual(len(cells), 9, rows[0])
        self.assertRegex(cells[7], r"^[0-9]+\.[0-9]{2} s$")  # as in scenarios/wear/RESULTS.md: "129.27 s"
        self.assertRegex(cells[8], r"^[0-9.]+ M$")  # "3.43 M"
        self.assertEqual(cells[1], "466")
        self.assertEqual(cells[2], "1750")
        return float(cells[7].split()[0])

    def test_wall_time_is_the_total_row_of_the_log(self):
        totals = self.totals(WORK / "junction.log")
        self.assertEqual(len(totals), 1)
        # RESULTS.md's command passes both the run directory and its log (out/wear/junction_*): one row.
        r = script(self.SCRIPT, WORK / "junction", WORK / "junction.log")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stderr, "")
        self.assertAlmostEqual(self.wall(r.stdout), totals[0], delta=0.0051)

    def test_a_log_of_several_runs_gives_the_last_total(self):
        both = WORK / "several" / "junction"
        shutil.copytree(WORK / "junction", both)
        both.with_name("junction.log").write_text((WORK / "junction.log").read_text() +
                                                  (WORK / "restart.log").read_text())
        totals = self.totals(both.with_name("junction.log"))
        self.assertEqual(len(totals), 2)
        r = script(self.SCRIPT, both)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("2 pass tables", r.stderr)
        self.assertAlmostEqual(self.wall(r.stdout), totals[-1], delta=0.0051)

    def test_without_a_log_the_wall_time_is_unknown(self):
        alone = WORK / "alone" / "junction"
        shutil.copytree(WORK / "junction", alone)
        r = script(self.SCRIPT, alone)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("no log", r.stderr)
        row = [line for line in r.stdout.splitlines() if line.startswith("| junction ")][0]
        self.assertTrue(row.endswith("| ? | ? |"), row)
        self.assertIn("| 466 |", row)  # N from the dump

    def test_wrong_folders(self):
        self.assertOneLineError(script(self.SCRIPT, WORK / "no_such_run"), "summarize.py", "no_such_run")
        self.assertOneLineError(script(self.SCRIPT, WORK / "no_such_run.log"), "summarize.py", "no_such_run")
        self.assertOneLineError(script(self.SCRIPT, WORK / "press"), "summarize.py", "wear.csv")
        # One wrong argument among good ones: no table at all.
        self.assertOneLineError(script(self.SCRIPT, WORK / "junction", WORK / "no_such_run"), "summarize.py")
        self.assertFalse((WORK / "no_such_run").exists())


class Plot(Helpers):
    SCRIPT = WEAR / "plot.py"

    def test_reads_the_first_dump_and_the_restart_and_names_what_it_wrote(self):
        pics = WORK / "pictures"
        r = script(self.SCRIPT, WORK / "junction", "--out", pics)
        self.assertEqual(r.returncode, 0, r.stderr)
        # Frames 0, 250, ..., 1000 from dump.lammpstrj, 1000 (the checkpoint's, dropped), 1250, ..., 1750 from
        # dump.restart1000.lammpstrj.
        self.assertIn("read 8 frames (steps 0 to 1750) from dump.lammpstrj, dump.restart1000.lammpstrj", r.stdout)
        steps = [int(s) for s in re.search(r"side views of steps ([0-9, ]+)", r.stdout).group(1).split(", ")]
        self.assertTrue(any(s < 1000 for s in steps) and any(s > 1000 for s in steps), steps)
        self.assertIn("wrote %s and %s" % (pics / "side_views.png", pics / "force.png"), r.stdout)
        self.assertEqual(sorted(p.name for p in pics.iterdir()), ["force.png", "side_views.png"])
        # Frame indices past the first chunk reach the restart's frames.
        r = script(self.SCRIPT, WORK / "junction", "--out", pics, "--frames", "0,7", "--prefix", "last_")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("side views of steps 0, 1750", r.stdout)

    def test_without_wear_csv_names_only_the_side_views(self):
        dumps = WORK / "dumps_only"
        dumps.mkdir()
        for name in ("dump.lammpstrj", "dump.restart1000.lammpstrj"):
            shutil.copy(WORK / "junction" / name, dumps / name)
        r = script(self.SCRIPT, dumps)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout.strip().splitlines()[-1], "wrote %s" % (dumps / "side_views.png"))
        self.assertFalse((dumps / "force.png").exists())

    def test_wrong_folders_create_nothing(self):
        missing = WORK / "no_such_run"
        self.assertOneLineError(script(self.SCRIPT, missing), "plot.py", str(missing))
        self.assertFalse(missing.exists())
        self.assertOneLineError(script(self.SCRIPT, missing, "--out", WORK / "no_such_out"), "plot.py")
        self.assertFalse((WORK / "no_such_out").exists())
        self.assertOneLineError(script(self.SCRIPT, WORK / "press", "--out", WORK / "no_such_out"), "plot.py",
                                "dump.lammpstrj")
        self.assertFalse((WORK / "no_such_out").exists())
        self.assertOneLineError(script(self.SCRIPT, WORK / "junction", "--frames", "0,8", "--out",
                                       WORK / "no_such_out"), "plot.py", "8 frames")
        self.assertFalse((WORK / "no_such_out").exists())


class PlotSizes(Helpers):
    """scenarios/patch/plot_sizes.py on two sizes' cases.csv (rows as debris_patch writes them)."""
    SCRIPT = SOURCE / "scenarios" / "patch" / "plot_sizes.py"
    HEADER = "case,test,sample,d0_over_dc,s,status,E_dev,nu,volume_fraction,strength_over_target\n"

    def write(self, name, rows):
        path = WORK / name
        path.write_text(self.HEADER + "".join(",".join(str(v) for v in r) + "\n" for r in rows))
        return path

    def test_merges_runs_of_one_size_and_counts_each_panel(self):
        small = self.write("small.csv", [(1, "elastic", "amorphous", 1.2, 0, "ok", -0.1, 0.159, 0.768, ""),
                                         (2, "elastic", "amorphous", 2.4, 0.5, "ok", -0.25, 0.159, 0.718, ""),
                                         (3, "tension", "amorphous", 1.2, 0, "ok", "", "", "", 0.579),
                                         (4, "tension", "hcp", 1.2, 0, "ok", "", "", "", 0.9),       # not amorphous
                                         (5, "shear", "amorphous", 1.2, 0, "failed", "", "", "", 0.8)])  # not ok
        # Two runs of the large size; the second repeats the first's case at 1.2 d_c, which keeps one point.
        a = self.write("large_a.csv", [(1, "elastic", "amorphous", 1.2, 0, "ok", -0.08, 0.157, 0.767, "")])
        b = self.write("large_b.csv", [(1, "elastic", "amorphous", 1.2, 0, "ok", -0.077, 0.157, 0.767, ""),
                                       (2, "elastic", "amorphous", 2.4, 0.5, "ok", -0.2, 0.157, 0.72, "")])
        out = WORK / "sizes"
        r = script(self.SCRIPT, "--size", "L = 12 d0", small, "--size", "L = 100 d0", a, b, "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("E / E_target (Fig 8): L = 12 d0 s=0: 1, L = 12 d0 s=0.5: 1, L = 100 d0 s=0: 1, "
                      "L = 100 d0 s=0.5: 1", r.stdout)
        self.assertIn("tensile strength / target (Fig A.7): L = 12 d0 s=0: 1\n", r.stdout)
        self.assertIn("shear strength / target (Fig A.8): no points", r.stdout)
        self.assertEqual([p.name for p in out.iterdir()], ["amorphous_sizes.png"])

    def test_wrong_files_write_nothing(self):
        out = WORK / "no_such_sizes"
        self.assertOneLineError(script(self.SCRIPT, "--size", "L", WORK / "no_such.csv", "--out", out),
                                "plot_sizes.py", "no_such.csv")
        bad = WORK / "not_cases.csv"
        bad.write_text("a,b\n1,2\n")
        self.assertOneLineError(script(self.SCRIPT, "--size", "L", bad, "--out", out), "plot_sizes.py",
                                "not a debris_patch cases.csv")
        self.assertFalse(out.exists())


class PlotDiscretisation(Helpers):
    """scenarios/patch/plot_discretisation.py on discretisation runs and a d0 sweep (rows as debris_patch writes)."""
    SCRIPT = SOURCE / "scenarios" / "patch" / "plot_discretisation.py"
    HEADER = "case,test,sample,d0_over_dc,s,status,strength,target_strength,outcome,system_size_over_dc\n"

    def write(self, name, rows):
        path = WORK / name
        path.write_text(self.HEADER + "".join(",".join(f'"{v}"' if "," in str(v) else str(v) for v in r) + "\n"
                                              for r in rows))
        return path

    def test_lines_per_size_and_rule_with_ratios_to_the_coarsest(self):
        fixed, scaled = "amorphous L=60 d_c, d_l fixed 3 d_c", "amorphous L=60 d_c, d_l = 1.25 d0"
        a = self.write("disc_a.csv", [(1, "tension", fixed, 2.4, 0.5, "ok", 0.06, 0.129, "broke", 60),
                                      (2, "tension", fixed, 1.2, 0.5, "ok", 0.07, 0.183, "broke", 60),
                                      (3, "tension", scaled, 1.2, 0.5, "failed", "", "", "", 60)])  # not ok
        b = self.write("disc_b.csv", [(3, "tension", scaled, 2.4, 0.5, "ok", 0.06, 0.129, "broke", 60),
                                      (4, "tension", scaled, 1.2, 0.5, "ok", 0.09, 0.183, "broke", 60)])
        # The d0 sweep at L = 100 d0: d0 = 0.6 d_c is L = 60 d_c (kept), 0.7 d_c is L = 70 d_c (not a size).
        sweep = self.write("sweep.csv", [(1, "elastic", "amorphous", 0.6, 0.5, "ok", "", "", "", ""),
                                         (2, "tension", "amorphous", 0.6, 0.5, "ok", 0.12, 0.2, "broke", ""),
                                         (3, "tension", "amorphous", 0.7, 0.5, "ok", 0.11, 0.2, "broke", "")])
        out = WORK / "discretisation"
        r = script(self.SCRIPT, a, b, "--scaled-from-sweep", sweep, "--sizes", "60", "120", "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("s=0.5 L=60 d_l fixed: n=25 0.06 (1.00), n=50 0.07 (1.17)\n", r.stdout)
        self.assertIn("s=0.5 L=60 d_l scaled: n=25 0.06 (1.00), n=50 0.09 (1.50), n=100 0.12 (2.00)\n", r.stdout)
        self.assertNotIn("L=70", r.stdout)
        self.assertEqual([p.name for p in out.iterdir()], ["discretisation.png"])

    def test_wrong_files_write_nothing(self):
        out = WORK / "no_such_discretisation"
        self.assertOneLineError(script(self.SCRIPT, WORK / "no_such.csv", "--out", out), "plot_discretisation.py",
                                "no_such.csv")
        bad = WORK / "not_cases_disc.csv"
        bad.write_text("a,b\n1,2\n")
        self.assertOneLineError(script(self.SCRIPT, bad, "--out", out), "plot_discretisation.py",
                                "not a debris_patch cases.csv")
        self.assertFalse(out.exists())


class Compression(Helpers):
    SCRIPT = PERIDEM / "compression.py"

    def test_a_run_too_short_for_the_press_is_refused(self):
        short = WORK / "press_short"
        for extra in ([], PRESS):  # the default press start (0.12 s) and the run's (0.2 ms)
            r = script(self.SCRIPT, short, *extra, "--pictures", WORK / "no_such_pictures")
            self.assertOneLineError(r, "compression.py", "press")
        self.assertFalse((short / "compression.csv").exists())
        self.assertFalse((WORK / "no_such_pictures").exists())

    def test_a_press_continued_by_a_restart(self):
        pics = WORK / "press_pictures"
        r = script(self.SCRIPT, WORK / "press", *PRESS, "--marks", "0.00005,0.00025", "--pictures", pics)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("(7 rows, t = 0.0002 to 0.00026 s)", r.stdout)
        with open(WORK / "press" / "compression.csv") as f:
            self.assertEqual(len(f.read().strip().splitlines()), 8)
        # t1 lies in trajectory.h5 (frames to 0.15 ms), t2 only in trajectory.restart1500.h5.
        self.assertTrue((WORK / "press" / "trajectory.restart1500.h5").exists())
        for name in ("compression_pressure.png", "compression_damage_t_1.png", "compression_damage_t_2.png"):
            self.assertIn("wrote %s" % (pics / name), r.stdout)
            self.assertTrue((pics / name).exists(), name)

    def test_wrong_folders(self):
        self.assertOneLineError(script(self.SCRIPT, WORK / "no_such_run", "--pictures", WORK / "no_such_pictures"),
                                "compression.py", "no_such_run")
        empty = WORK / "empty"
        empty.mkdir(exist_ok=True)
        self.assertOneLineError(script(self.SCRIPT, empty), "compression.py", "thermo.csv")
        self.assertOneLineError(script(self.SCRIPT, WORK / "junction"), "compression.py", "lid_fy")
        self.assertFalse((WORK / "no_such_pictures").exists())
        self.assertFalse((WORK / "no_such_run").exists())


class OtherPeridemScripts(Helpers):
    def test_damage_picture(self):
        s = PERIDEM / "damage_picture.py"
        to = WORK / "no_such_pictures"
        self.assertOneLineError(script(s, WORK / "no_such_run", "0.0001", "--to", to), "damage_picture.py")
        (WORK / "empty_too").mkdir()
        self.assertOneLineError(script(s, WORK / "empty_too", "0.0001", "--to", to), "damage_picture.py",
                                "trajectory.h5")
        self.assertOneLineError(script(s, WORK / "junction", "0.0001", "--to", to), "damage_picture.py",
                                "not a debris_peridem trajectory")
        self.assertFalse(to.exists())
        pics = WORK / "damage"
        r = script(s, WORK / "press", "0.0001", "0.00025", "--to", pics)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted(p.name for p in pics.iterdir()), ["damage_1.png", "damage_2.png"])

    def test_settled_pack_wrong_paths(self):
        s = PERIDEM / "settled_pack.py"
        traj = WORK / "press" / "trajectory.h5"
        particles = WORK / "particles.csv"
        particles.write_text("i, x, y, z, r, o\n")
        self.assertOneLineError(script(s, WORK / "no_such_run" / "trajectory.h5", particles, WORK / "out.csv"),
                                "settled_pack.py", "trajectory")
        self.assertOneLineError(script(s, traj, WORK / "no_such.csv", WORK / "out.csv"), "settled_pack.py",
                                "particle list")
        self.assertOneLineError(script(s, traj, particles, WORK / "no_such_dir" / "out.csv"), "settled_pack.py")
        self.assertOneLineError(script(s, traj, particles, WORK / "out.csv", "--reference", WORK / "nope.h5"),
                                "settled_pack.py", "--reference")
        self.assertFalse((WORK / "out.csv").exists())
        self.assertFalse((WORK / "no_such_dir").exists())


class RoughPlot(Helpers):
    SCRIPT = ROUGH / "plot.py"

    def test_draws_the_faces_and_names_what_it_wrote(self):
        pics = WORK / "rough_pictures"
        pics.mkdir()
        r = script(self.SCRIPT, WORK / "rough", "--out", pics)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("bottom first: H", r.stdout)
        self.assertIn("wrote %s and %s" % (pics / "roughness.png", pics / "faces.png"), r.stdout)
        self.assertEqual(sorted(p.name for p in pics.iterdir()), ["faces.png", "roughness.png"])

    def test_wrong_folders_create_nothing(self):
        self.assertOneLineError(script(self.SCRIPT, WORK / "no_such_run"), "plot.py", "surfaces.csv")
        self.assertOneLineError(script(self.SCRIPT, WORK / "junction"), "plot.py", "junction/surfaces.csv")
        self.assertOneLineError(script(self.SCRIPT, WORK / "rough", "--out", WORK / "no_such_out"), "plot.py",
                                "no_such_out")
        self.assertFalse((WORK / "no_such_out").exists())


if __name__ == "__main__":
    argv = sys.argv[1:]
    # The bin directory: the first argument when it is a directory, else DEBRIS_BIN_DIR (the other
    # arguments go to unittest: test names, -k PATTERN, ...).
    if argv and os.path.isdir(argv[0]):
        where = argv.pop(0)
    else:
        where = os.environ.get("DEBRIS_BIN_DIR") or (argv.pop(0) if argv and not argv[0].startswith("-") else None)
    if not where:
        sys.exit("usage: test_helper_scripts.py BUILD/bin [unittest options] (or set DEBRIS_BIN_DIR)")
    BIN = pathlib.Path(where).resolve()
    for exe in ("debris_dem", "debris_peridem"):
        if not (BIN / exe).is_file():
            sys.exit("test_helper_scripts.py: no %s in %s" % (exe, BIN))
    unittest.main(argv=[sys.argv[0]] + argv, verbosity=2)
