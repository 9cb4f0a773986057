#!/usr/bin/python3
"""Pictures of a rough-surface wear run (scenarios/rough): how the faces' roughness evolves and what wears off.
Headless PNGs (Debian's python3-matplotlib, python3-numpy, python3-h5py).

    /usr/bin/python3 scenarios/rough/plot.py out/rough/rough_H0.8_rms2nm [--out DIR]

Reads surfaces.csv, surfaces_heights.h5 and surfaces_debris.csv from the run's directory (the wear census,
scenarios/dem/README.md) and writes into --out (default: the run's directory):
  roughness.png  the faces' PSD at the first and the last sample (log-log, the fitted self-affine slope drawn over
                 the census's fit range), their rms height and Hurst exponent against the sliding distance, the wear
                 volume against the sliding distance and against the tangential work, the wear particles' sizes
  faces.png      the two faces' height maps at the first and the last sample, seen from above
and prints the fitted exponents it drew. A wrong run directory (none, or no surfaces.csv or surfaces_heights.h5 in
it) is one line on stderr and exit status 2, before anything is written.
"""
import argparse
import csv
import math
import pathlib
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def fail(message):
    print(f"plot.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in (rows[0].keys() if rows else [])}


def psd(h, la, lb):
    """Radially averaged PSD (C = A |h_k|^2, the census's convention) of a periodic map, in bins of |q| of
    width 2 pi / max(la, lb)."""
    na, nb = h.shape
    hk = np.fft.fft2(h - h.mean()) / h.size
    qa = 2 * np.pi * np.fft.fftfreq(na, d=la / na)
    qb = 2 * np.pi * np.fft.fftfreq(nb, d=lb / nb) if nb > 1 else np.zeros(1)
    q = np.hypot(*np.meshgrid(qa, qb, indexing="ij"))
    c = la * (lb if nb > 1 else 1.0) * np.abs(hk) ** 2
    dq = 2 * np.pi / max(la, lb if nb > 1 else la)
    k = np.rint(q / dq).astype(int)
    keep = k > 0
    sums = np.bincount(k[keep], weights=c[keep])
    qs = np.bincount(k[keep], weights=q[keep])
    n = np.bincount(k[keep])
    ok = n > 0
    return qs[ok] / n[ok], sums[ok] / n[ok]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run", type=pathlib.Path)
    ap.add_argument("--out", type=pathlib.Path)
    a = ap.parse_args()
    run = a.run
    for name in ("surfaces.csv", "surfaces_heights.h5"):
        if not (run / name).is_file():
            fail(f"{run / name}: no such file (run debris_dem with a surfaces: section and roughness height maps)")
    out = a.out or run
    if not out.is_dir():
        fail(f"{out}: no such folder for the pictures")
    s = read_csv(run / "surfaces.csv")
    if not s or len(s["step"]) == 0:
        fail(f"{run / 'surfaces.csv'}: no samples")
    debris = read_csv(run / "surfaces_debris.csv") if (run / "surfaces_debris.csv").is_file() else {}
    with h5py.File(run / "surfaces_heights.h5", "r") as f:
        spacing = f.attrs["spacing"]
        samples = f["samples"]
        last = str(len(samples) - 1)
        maps = {(when, face): np.array(samples[k][face]) for when, k in (("first", "0"), ("last", last))
                for face in ("bottom", "top")}
    slide = s["slide"] * 1e9

    fig, ax = plt.subplots(2, 3, figsize=(15, 8.5))
    # PSD, first and last, both faces.
    p = ax[0, 0]
    printed = []
    for (when, face), h in maps.items():
        if not np.isfinite(h).all() or h.size < 4:
            continue
        la, lb = spacing[0] * h.shape[0], spacing[1] * h.shape[1]
        q, c = psd(h, la, lb)
        style = "-" if when == "last" else ":"
        p.loglog(q * 1e-9, c, style, label=f"{face} face, {when} sample")
        hurst = s[f"{face}_hurst"][0 if when == "first" else -1]
        printed.append(f"{face} {when}: H = {hurst:.3g}" if math.isfinite(hurst) else f"{face} {when}: H not fitted")
    p.set_xlabel("q (1/nm)")
    p.set_ylabel("C(q) (m^4)")
    p.set_title("power spectral density")
    p.legend(fontsize=8)
    # rms height and H against the slide.
    p = ax[0, 1]
    for face in ("bottom", "top"):
        p.plot(slide, s[f"{face}_rms_height"] * 1e9, label=f"{face} rms height")
    p.set_xlabel("sliding distance (nm)")
    p.set_ylabel("rms height (nm)")
    p.legend(fontsize=8)
    p2 = p.twinx()
    for face, m in (("bottom", "o"), ("top", "s")):
        p2.plot(slide, s[f"{face}_hurst"], m, ms=3, alpha=0.6, label=f"{face} H")
    p2.axhline(0.8, ls="--", c="k", lw=0.8)
    p2.set_ylabel("Hurst exponent (dashed: 0.8, the MD's steady state)")
    p2.set_ylim(0, 1.2)
    # Wear volume against slide and against tangential work.
    p = ax[0, 2]
    p.plot(slide, s["wear_volume"] * 1e27, label="wear volume (by f)")
    p.plot(slide, s["detached_volume"] * 1e27, label="detached volume (by the graph)")
    p.set_xlabel("sliding distance (nm)")
    p.set_ylabel("volume (nm^3)")
    p.legend(fontsize=8)
    p = ax[1, 0]
    w, v = s["tangential_work"], s["wear_volume"]
    ok = (w > 0) & (v > 0)
    if ok.sum() >= 2:
        p.loglog(w[ok], v[ok] * 1e27, ".")
        slope, icpt = np.polyfit(np.log(w[ok]), np.log(v[ok]), 1)
        p.loglog(w[ok], np.exp(icpt + slope * np.log(w[ok])) * 1e27, "-", label=f"V ~ W_t^{slope:.2f}")
        p.legend(fontsize=8)
        printed.append(f"wear volume ~ W_t^{slope:.3g} over {ok.sum()} samples")
    p.set_xlabel("tangential work of the drives (J)")
    p.set_ylabel("wear volume (nm^3)")
    # Wear particles: volume against their tangential work (all samples), and sizes at the last sample.
    p = ax[1, 1]
    if debris and len(debris.get("step", [])):
        wt, vd = debris["tangential_work"], debris["volume"]
        ok = np.isfinite(wt) & (wt > 0) & (vd > 0)
        if ok.any():
            p.loglog(wt[ok], vd[ok] * 1e27, ".", alpha=0.4)
        p.set_xlabel("wear particle's tangential work W_t (J)")
        p.set_ylabel("its volume V_d (nm^3)")
        last_step = debris["step"].max()
        d = debris["diameter"][debris["step"] == last_step] * 1e9
        ax[1, 2].hist(d, bins=max(3, int(math.sqrt(len(d)))) if len(d) else 3)
    ax[1, 2].set_xlabel("equivalent diameter at the last sample (nm)")
    ax[1, 2].set_ylabel("wear particles")
    fig.tight_layout()
    fig.savefig(out / "roughness.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    for r, when in enumerate(("first", "last")):
        for c, face in enumerate(("bottom", "top")):
            h = maps[(when, face)]
            im = ax[r, c].imshow(h.T * 1e9, origin="lower", cmap="viridis",
                                 extent=[0, spacing[0] * h.shape[0] * 1e9, 0, spacing[1] * h.shape[1] * 1e9])
            ax[r, c].set_title(f"{face} face, {when} sample (nm)")
            ax[r, c].set_xlabel("slide axis (nm)")
            fig.colorbar(im, ax=ax[r, c])
    fig.tight_layout()
    fig.savefig(out / "faces.png", dpi=90)
    plt.close(fig)
    print("; ".join(printed))
    print(f"wrote {out / 'roughness.png'} and {out / 'faces.png'}")


if __name__ == "__main__":
    main()
