#!/usr/bin/env python3
"""Writes the six sheared-junction inputs of paper A section 4 (D = 10 and 20 nm, d0 = 1.5, 3 and 6 nm)
from the relaxed samples in data/ (made by sample_d0_*nm.yaml with debris_amorphous). The geometry is
placed in each sample's own relaxed box (the box grows by ~2% while relaxing), so the numbers differ a
little between samples; this script is how they were derived.

    python3 scenarios/wear/make_inputs.py      # rewrites scenarios/wear/junction_D*_d0_*nm.yaml
"""
import pathlib

HERE = pathlib.Path(__file__).resolve().parent

TABLE5 = """material:                      # Table 5, s = 0.5
  youngs_modulus: 73 GPa
  poisson_ratio: 0.17
  tensile_strength: 16 GPa
  shear_strength: 9 GPa
  surface_energy: 1.5 N/m
  restitution: 0.9
  density: 2200 kg/m^3
  scaling: 0.5
"""
# debris_calibrate's answer for Table 5 on the junction's sample recipe (d_l = 7.5 nm, seed 1): its sample
# measures E = 73 GPa, nu 0.167, tension 11.5 GPa (16 is out of reach), shear 8.3 GPa (scenarios/patch/RESULTS.md).
CALIBRATED_3NM = """material:                      # calibrated silica (debris_calibrate), s = 0.5
  youngs_modulus: 73.383441 GPa
  poisson_ratio: 0.17
  tensile_strength: 16.084042 GPa
  shear_strength: 13.57091 GPa
  surface_energy: 5.2197049 N/m
  restitution: 0.9
  density: 2200 kg/m^3
  scaling: 0.5
"""

# Per d0: the sample, the time step of Table 6, and the analysis sampling interval (0.05 ns) in steps.
CASES = {
    "1.5": dict(data="data/silica_d0_1.5nm.data", dt_fs=20),
    "3": dict(data="data/silica_d0_3nm.data", dt_fs=40),
    "6": dict(data="data/silica_d0_6nm.data", dt_fs=80),
    # Two more samples at d0 = 6 nm (seeds 2 and 3 of sample_d0_6nm_seed*.yaml), for the seed study and ctest.
    "6_seed2": dict(data="data/silica_d0_6nm_seed2.data", dt_fs=80, d0=6),
    "6_seed3": dict(data="data/silica_d0_6nm_seed3.data", dt_fs=80, d0=6),
    "3_seed2": dict(data="data/silica_d0_3nm_seed2.data", dt_fs=40, d0=3),
    "3_seed3": dict(data="data/silica_d0_3nm_seed3.data", dt_fs=40, d0=3),
    # And at d0 = 1.5 nm, where D = 20 nm rolls on seed 1: does it roll on every sample?
    "1.5_seed2": dict(data="data/silica_d0_1.5nm_seed2.data", dt_fs=20, d0=1.5),
    "1.5_seed3": dict(data="data/silica_d0_1.5nm_seed3.data", dt_fs=20, d0=1.5),
    # Calibrated silica at d0 = 3 nm (sample_d0_3nm_calibrated.yaml): the inputs debris_calibrate returned for
    # this recipe, whose sample measures 73 GPa and the closest reachable strengths.
    "3_calibrated": dict(data="data/silica_d0_3nm_calibrated.data", dt_fs=40, d0=3, material=CALIBRATED_3NM),
    # Its control: Table 5 with the surface energy half way (in log) to the calibrated one.
    "3_gamma3.4": dict(data="data/silica_d0_3nm_gamma3.4.data", dt_fs=40, d0=3,
                       material=TABLE5.replace("surface_energy: 1.5 N/m", "surface_energy: 3.3749 N/m")
                                      .replace("# Table 5, s = 0.5", "# Table 5 with 3.3749 N/m, s = 0.5")),
}
SETTLE_NS = 0.2      # settling under the load before sliding (the paper is silent): see README
SLIDE_NS = 10.0      # 10 ns of sliding (Table 6)
SAMPLE_NS = 0.05     # wear analysis and thermo interval
FRAME_NS = 0.5       # dump / trajectory frames


def box_of(data):
    lo, hi = [0.0] * 3, [0.0] * 3
    for line in (HERE / data).read_text().splitlines()[:12]:
        parts = line.split()
        for axis, name in enumerate("xyz"):
            if len(parts) == 4 and parts[2] == name + "lo":
                lo[axis], hi[axis] = float(parts[0]), float(parts[1])
    return lo, hi


def nm(v):
    return f"{v * 1e9:.4f} nm"


def write(d0, D, load_mpa=100, settle=True, slide_ns=SLIDE_NS, variant="", folder=HERE):
    case = CASES[d0]
    lo, hi = box_of(case["data"])
    d0_m = float(case.get("d0", d0)) * 1e-9
    D_m = D * 1e-9
    H = D_m / 2
    xc, yc, zc = [(a + b) / 2 for a, b in zip(lo, hi)]
    gap = (yc - H / 2, yc + H / 2)
    wall = 1.5 * d0_m
    dt = case["dt_fs"] * 1e-15
    steps = lambda ns: int(round(ns * 1e-9 / dt))
    cylinder = (f"{{cylinder: {{axis: y, centre: [{nm(xc)}, 0, {nm(zc)}], radius: {nm(D_m / 2)}, "
                f"extent: [{nm(gap[0])}, {nm(gap[1])}]}}}}")
    d0_label, _, seed = d0.partition("_")
    name = f"junction_D{D}_d0_{d0_label}nm" + (f"_{seed}" if seed else "") + variant
    data = case["data"] if folder == HERE else "../" + case["data"]
    settle_stage = f"""  - name: settle               # the carved faces relax under the load, damped
    duration: {SETTLE_NS} ns
    global_damping: 0.1
""" if settle else ""
    sample = (f" (sample {seed.replace('seed', 'seed ')})" if seed.startswith("seed")
              else " (calibrated silica)" if seed == "calibrated"
              else f" (Table 5, surface energy {seed[len('gamma'):]} N/m)" if seed else "")
    material = case.get("material", TABLE5)
    text = f"""# Sheared junction of paper A section 4 (Figs 9, 10, A.10): D = {D} nm, d0 = {d0_label} nm{sample}. Two amorphous silica
# bodies joined by a cylinder of diameter D and height D/2 (axis y), rigid walls {1.5 * d0_m * 1e9:g} nm (1.5 d0)
# thick at the outer faces; the bottom wall is fixed, the top wall slides at 10 m/s along x under a normal
# load of 100 MPa (y free), z fixed. Written by make_inputs.py from the relaxed sample in {case['data']}
# (box {nm(hi[0] - lo[0])} x {nm(hi[1] - lo[1])} x {nm(hi[2] - lo[2])}). Run:
#   build/bin/debris_dem -i scenarios/wear/{name}.yaml
# The wear analysis decides ductile or rolling wear particle (wear.csv, the closing lines); see README.
{material}
particles:
  lammps_data: {data}
  masses_from_file: true       # the relaxed sample's masses (total mass / box volume = rho)

box:
  periodic: [true, false, true]  # periodic along the sliding axis x and along z; y is the normal

remove:                        # the gap between the bodies, except the junction
  difference:
    - {{block: {{y: [{nm(gap[0])}, {nm(gap[1])}]}}}}
    - {cylinder}

labels:                        # the body each particle starts in (later entries override earlier ones)
  - {{name: bottom, region: {{block: {{y: [-inf, {nm(yc)}]}}}}}}
  - {{name: top, region: {{block: {{y: [{nm(yc)}, inf]}}}}}}
  - {{name: junction, region: {cylinder}}}
  - {{name: bottom_wall, region: {{block: {{y: [-inf, {nm(lo[1] + wall)}]}}}}}}
  - {{name: top_wall, region: {{block: {{y: [{nm(hi[1] - wall)}, inf]}}}}}}

groups:
  - name: bottom_wall
    region: {{block: {{y: [-inf, {nm(lo[1] + wall)}]}}}}
    motion: frozen
  - name: top_wall
    region: {{block: {{y: [{nm(hi[1] - wall)}, inf]}}}}
    motion: force              # rigid: y moves under the load, x and z prescribed
    velocity: [0, free, 0]     # at rest while settling
    stress: [0, -{load_mpa} MPa, 0]   # times the x-z area of the box

stages:
{settle_stage}  - name: slide
    duration: {slide_ns} ns
    global_damping: 0
    groups:
      - {{name: top_wall, motion: force, velocity: [10 m/s, free, 0], stress: [0, -{load_mpa} MPa, 0]}}

run:
  time_step: {case['dt_fs']} fs              # Table 6
  overlap_limit: auto          # relaxed samples hold overlaps of 0.6-1.3 r_min
  skin: 0.5 nm                 # carving leaves vibration: a wide skin keeps rebuilds rare (README)
  # threads: left to the tuner (two pay at d0 = 1.5 nm, one at 6 nm: RESULTS.md, Cost)

wear:
  every: {steps(SAMPLE_NS)}                   # steps: {SAMPLE_NS} ns
  bottom_wall: bottom_wall
  top_wall: top_wall
  junction_label: junction
  sliding_axis: x
  normal_axis: y
  window: 2 ns                 # motion over the last 2 ns (20 nm of sliding) decides
  moving: [0.1, 0.9]           # particles moving with neither wall: 0.1 < f < 0.9 of the wall's displacement
  min_volume_fraction: 0.25    # a wear particle holds at least a quarter of the junction's volume
  max_residual: 0.3            # it moves rigidly: rigid-fit residual / displacement spread (rigid ~0, shear ~0.7)
  residual_floor: 0.25         # ... or / (0.25 x the walls' relative slide), for a body that does not spin
  verdict_span: 1 ns           # the verdict: a rigid candidate at every sample of the last 1 ns, judged on its means
  centre_speed: [0.25, 0.75]   # of the wall's (rolling without slip: 0.5)
  rolling_number: [0.5, 1.5]   # 2 R omega / v (rolling without slip: 1)
  persistence: 2.5 ns          # diagnostics only: a pair in range this long counts as a bond

surfaces:                      # the wear census of the interface (surfaces.csv, surfaces_histogram.csv)
  every: {steps(SAMPLE_NS)}                   # steps: {SAMPLE_NS} ns
  bottom: {{label: [bottom, bottom_wall], driven: bottom_wall}}
  top: {{label: [top, junction, top_wall], driven: top_wall}}  # the junction starts with the top body
  sliding_axis: x
  normal_axis: y
  window: 2 ns                 # f over the last 2 ns, as the wear analysis's
  moving: [0.1, 0.9]           # 0.1 < f < 0.9: moving with neither body (the third body)

output:
  directory: out/wear/{name if folder == HERE else "study/" + name}
  thermo_every: {steps(SAMPLE_NS)}
  dump_every: {steps(FRAME_NS)}
  checkpoint_every: {steps(1.0)}        # 1 ns
  progress_seconds: 30
"""
    (folder / f"{name}.yaml").write_text(text)
    return name


if __name__ == "__main__":
    for d0 in CASES:
        for D in (10, 20):
            print(write(d0, D))
    # The set-up study of D = 20 nm at d0 = 6 and 3 nm (the paper leaves these unstated): one change at a
    # time from the inputs above, on three samples each.
    study = HERE / "study"
    study.mkdir(exist_ok=True)
    for d0 in ("6", "6_seed2", "6_seed3", "3", "3_seed2", "3_seed3"):
        print(write(d0, 20, load_mpa=10, variant="_load10MPa", folder=study))
        print(write(d0, 20, settle=False, variant="_nosettle", folder=study))
        print(write(d0, 20, slide_ns=20.0, variant="_20ns", folder=study))
