#!/usr/bin/env python3
"""Writes the rough-surface wear inputs (scenarios/rough/*.yaml): two amorphous silica bodies (Table 5, s = 0.5,
the junctions' material) with self-affine faces, pressed together and slid. The bodies are the junctions'
relaxed samples (scenarios/wear/data), tiled along the interface with particles.replicate.

    python3 scenarios/rough/make_inputs.py      # rewrites scenarios/rough/rough_*.yaml

Geometry (normal y, slide x, periodic along x and z):
  bottom body   the points below surface s1 (mean height y_mid - gap / 2)
  top body      the points above surface s2 (mean height y_mid + gap / 2), except those less than `clearance`
                above s1: where a peak of s1 reaches past s2, the top face follows s1 at that distance, so the
                faces start apart everywhere and touch at their highest asperities
  walls         the outer 1.5 d0 of each body: the bottom one frozen, the top one force-driven (the normal
                stress, rigid) and, once settled, slid at a constant velocity along x
"""
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
WEAR = HERE.parent / "wear"
sys.dont_write_bytecode = True  # no __pycache__ left in scenarios/wear
sys.path.insert(0, str(WEAR))
from make_inputs import TABLE5, box_of, nm  # noqa: E402  (the junctions' material, sample boxes, lengths)

SAMPLES = {  # d0 (nm): the relaxed sample and Table 6's time step
    "3": dict(data="data/silica_d0_3nm.data", dt_fs=40),
    "6": dict(data="data/silica_d0_6nm.data", dt_fs=80),
}
LARGEST_DIAMETER = 7.47e-9  # every silica sample's (d_l = 7.5 nm): a surface's shortest wavelength is >= 2 of it


def write(name, d0, tiles, hurst, rms_nm, cutoff_nm, slide_ns, sample_ps, settle_ns=0.2, load_mpa=100,
          speed=10, seeds=(1, 2), clearance_nm=1.0, frame_ns=1.0, checkpoint_ns=1.0, comment=""):
    s = SAMPLES[d0]
    lo, hi = box_of(s["data"])
    length = [(b - a) * n for a, b, n in zip(lo, hi, tiles)]
    top = [a + l for a, l in zip(lo, length)]
    y_mid = (lo[1] + top[1]) / 2
    rms = rms_nm * 1e-9
    gap = 2 * rms  # the faces' mean separation: their highest asperities overlap (and are cut by the clearance)
    wall = 1.5 * float(d0) * 1e-9
    dt = s["dt_fs"] * 1e-15
    steps = lambda t: int(round(t / dt))
    every = steps(sample_ps * 1e-12)
    grid = min(cutoff_nm / 4, 1.0)

    def surface(seed, at, side):
        return (f"{{surface: {{normal: y, side: {side}, at: {nm(at)}, grid_spacing: {grid:g} nm, self_affine: "
                f"{{hurst: {hurst}, rms_height: {rms_nm:g} nm, cutoff_wavelength: {cutoff_nm:g} nm, seed: {seed}}}}}}}")

    s1 = lambda at, side: surface(seeds[0], at, side)
    bottom = s1(y_mid - gap / 2, "below")
    top_body = (f"{{difference: [{surface(seeds[1], y_mid + gap / 2, 'above')}, "
                f"{s1(y_mid - gap / 2 + clearance_nm * 1e-9, 'below')}]}}")
    if hurst is None:  # a flat pair: the faces are planes one clearance apart
        bottom = f"{{block: {{y: [-inf, {nm(y_mid)}]}}}}"
        top_body = f"{{block: {{y: [{nm(y_mid + clearance_nm * 1e-9)}, inf]}}}}"
    n = 1
    for t in tiles:
        n *= t
    faces = (f"self-affine faces (H = {hurst},\n# rms height {rms_nm:g} nm, wavelengths {cutoff_nm:g} nm to the box's length)"
             if hurst is not None else "flat faces (the control)")
    text = f"""# Wear of rough surfaces{comment}: two amorphous silica bodies with {faces}, pressed together at {load_mpa} MPa and slid at
# {speed} m/s along x for {slide_ns:g} ns ({speed * slide_ns:g} nm, {speed * slide_ns * 1e-9 / length[0]:.2f} box lengths). The sample in ../wear/{s['data']}
# (d0 = {d0} nm) tiled {tiles[0]} x {tiles[1]} x {tiles[2]}: box {nm(length[0])} x {nm(length[1])} x {nm(length[2])}. Written by make_inputs.py. Run:
#   build/bin/debris_dem -i scenarios/rough/{name}.yaml
{TABLE5}
particles:
  lammps_data: ../wear/{s['data']}
  masses_from_file: true       # the relaxed sample's masses
  replicate: [{tiles[0]}, {tiles[1]}, {tiles[2]}]       # a periodic sample continues across every seam (manual)

box:
  periodic: [true, false, true]  # along the slide x and across it z; y is the normal

remove:                        # between the two faces
  difference:
    - {{block: {{}}}}
    - {bottom}
    - {top_body}

labels:                        # the body each particle starts in
  - {{name: bottom, region: {bottom}}}
  - {{name: top, region: {top_body}}}
  - {{name: bottom_wall, region: {{block: {{y: [-inf, {nm(lo[1] + wall)}]}}}}}}
  - {{name: top_wall, region: {{block: {{y: [{nm(top[1] - wall)}, inf]}}}}}}

groups:
  - name: bottom_wall
    region: {{block: {{y: [-inf, {nm(lo[1] + wall)}]}}}}
    motion: frozen
  - name: top_wall
    region: {{block: {{y: [{nm(top[1] - wall)}, inf]}}}}
    motion: force              # rigid: y moves under the load, x and z prescribed
    velocity: [0, free, 0]     # at rest while settling
    stress: [0, -{load_mpa} MPa, 0]   # times the x-z area of the box

stages:
  - name: settle               # the faces meet under the load, damped
    duration: {settle_ns:g} ns
    global_damping: 0.1
  - name: slide
    duration: {slide_ns:g} ns
    global_damping: 0
    groups:
      - {{name: top_wall, motion: force, velocity: [{speed} m/s, free, 0], stress: [0, -{load_mpa} MPa, 0]}}

run:
  time_step: {s['dt_fs']} fs              # Table 6
  overlap_limit: auto          # relaxed samples hold overlaps of 0.6-1.3 r_min
  skin: 0.5 nm

surfaces:                      # the wear census (surfaces.csv, surfaces_histogram.csv, surfaces_debris.csv)
  every: {every}                  # steps: {sample_ps:g} ps
  bottom: {{label: [bottom, bottom_wall], driven: bottom_wall}}
  top: {{label: [top, top_wall], driven: top_wall}}
  sliding_axis: x
  normal_axis: y
  window: {min(2.0, slide_ns / 2):g} ns
  moving: [0.1, 0.9]

output:
  directory: out/rough/{name}
  thermo_every: {every}
  dump_every: {steps(frame_ns * 1e-9)}
  checkpoint_every: {steps(checkpoint_ns * 1e-9)}
  progress_seconds: 30
"""
    (HERE / f"{name}.yaml").write_text(text)
    return name, n


if __name__ == "__main__":
    # The reduced input CI runs (seconds): one d0 = 6 nm sample, untiled, a short slide.
    print(write("rough_small", "6", (1, 1, 1), 0.8, 2.0, 15.0, slide_ns=0.6, sample_ps=20, settle_ns=0.1,
                frame_ns=0.1, checkpoint_ns=0.25, comment=" (reduced: the CI's input)"))
    # The 3D study: the d0 = 3 nm sample tiled 2 x 2 x 6 (58,536 particles, box 121 x 80 x 241 nm), slid four
    # box lengths (48 ns, 483 nm) at 10 m/s; samples every 50 ps. The shortest wavelength is 15 nm, two of
    # the samples' largest diameters.
    study = dict(d0="3", tiles=(2, 2, 6), cutoff_nm=15.0, slide_ns=48.0, sample_ps=50, frame_ns=2.0,
                 checkpoint_ns=1.0)
    print(write("rough_H0.8_rms2nm", hurst=0.8, rms_nm=2.0, **study))
    print(write("rough_H0.5_rms2nm", hurst=0.5, rms_nm=2.0, **study))
    print(write("rough_H0.8_rms4nm", hurst=0.8, rms_nm=4.0, **study))
    print(write("rough_H0.5_rms4nm", hurst=0.5, rms_nm=4.0, **study))
    print(write("rough_flat", hurst=None, rms_nm=0.0, **study))
    # The large input (10^6 particles: the sample tiled 8 x 2 x 28, box 483 x 80 x 1126 nm) for the rate on
    # MPI ranks: a short stretch of slide.
    print(write("rough_large", "3", (8, 2, 28), 0.8, 2.0, 15.0, slide_ns=0.2, sample_ps=50, settle_ns=0.05,
                frame_ns=1.0, checkpoint_ns=1.0, comment=" (10^6 particles, for the rate)"))
