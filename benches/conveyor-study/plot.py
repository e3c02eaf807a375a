#!/usr/bin/env python3
"""Plots of the full conveyor's runs side by side (issue 30; docs/pneumatic-conveying.md):

    benches/conveyor-study/plot.py OUT_DIR LABEL=RUN [LABEL=RUN …]

writes into OUT_DIR
  stacks_distribution.png  where the particles are against time: out through the vented outlet
                           (cumulative), in the secondary chamber, in the vented leg, still in
                           the annulus and plenum (one line style per run);
  stacks_particle_velocity.png  the particles' mean axial velocity in the downstream tube
                           against time (steps with particles there), the experiment's 5–6 m/s
                           band shaded;
  stacks_air_path.png      the air's time-mean velocity (t >= 0.01 s) at the `path` probes:
                           |U| along the tube's axis (z) and U_x along the vented leg (x).
Each RUN is a run directory (its postProcessing/integrals.csv and CFD/postProcessing/path/0/U).
Needs matplotlib (Debian: python3-matplotlib).
"""
import csv
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out_dir = sys.argv[1]
runs = [a.split("=", 1) for a in sys.argv[2:]]
styles = ["-", "--", ":", "-."]


def integrals(run):
    rows = list(csv.DictReader(open(f"{run}/postProcessing/integrals.csv")))
    num = lambda r, k: float(r[k]) if r[k] not in ("", "nan") else None
    out, acc = [], 0
    for r in rows:
        acc += int(float(r["particles_out"]))
        out.append(acc)
    return rows, num, out


fig, ax = plt.subplots(figsize=(7, 4.2))
for (label, run), ls in zip(runs, styles):
    rows, num, out = integrals(run)
    t = [float(r["time"]) for r in rows]
    series = {
        "out (vented)": out,
        "secondary chamber": [num(r, "secondary_particles") for r in rows],
        "vented leg": [num(r, "vent_leg_particles") for r in rows],
        "annulus + plenum": [num(r, "chamber_particles") for r in rows],
    }
    for (name, y), colour in zip(series.items(), ["C0", "C1", "C2", "C3"]):
        ax.plot(t, y, ls, color=colour, label=f"{name}, {label}")
ax.set_xlabel("t (s)")
ax.set_ylabel("particles")
ax.legend(fontsize=7, ncol=2)
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(f"{out_dir}/stacks_distribution.png", dpi=90)

fig, ax = plt.subplots(figsize=(7, 3.6))
ax.axhspan(5, 6, color="0.85", label="experiment 5–6 m/s")
for (label, run), ls in zip(runs, styles):
    rows, num, _ = integrals(run)
    pts = [(float(r["time"]), num(r, "tube_axial_velocity")) for r in rows
           if (num(r, "tube_particles") or 0) > 0 and num(r, "tube_axial_velocity") is not None]
    ax.plot([p[0] for p in pts], [p[1] for p in pts], ls, label=label)
ax.set_xlabel("t (s)")
ax.set_ylabel("particle axial velocity in the tube (m/s)")
ax.legend(fontsize=8)
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(f"{out_dir}/stacks_particle_velocity.png", dpi=90)


def path_means(run):
    pts, sums, n = [], None, 0
    for line in open(f"{run}/CFD/postProcessing/path/0/U"):
        if line.startswith("# Probe") and "(" in line:
            pts.append(tuple(float(x) for x in line.split("(", 1)[1].rstrip(")\n").split()))
            continue
        if line.startswith("#") or not line.strip():
            continue
        if float(line.split()[0]) < 0.01:
            continue
        vals = [tuple(map(float, v.split())) for v in re.findall(r"\(([^)]*)\)", line)]
        sums = vals if sums is None else [tuple(a + b for a, b in zip(s, v)) for s, v in zip(sums, vals)]
        n += 1
    return pts, [tuple(c / n for c in s) for s in sums]


fig, (a1, a2) = plt.subplots(1, 2, figsize=(8, 3.4))
for (label, run), ls in zip(runs, styles):
    pts, mean = path_means(run)
    axis = [(p[2], (u[0] ** 2 + u[1] ** 2 + u[2] ** 2) ** 0.5) for p, u in zip(pts, mean)
            if p[0] == 0 and p[1] == 0]
    leg = [(p[0], u[0]) for p, u in zip(pts, mean) if p[0] > 0 and abs(p[2] - 0.1595) < 1e-9]
    a1.plot([1e3 * z for z, _ in axis], [v for _, v in axis], ls + "o", ms=3, label=label)
    a2.plot([1e3 * x for x, _ in leg], [v for _, v in leg], ls + "o", ms=3, label=label)
a1.set_xlabel("z along the tube's axis (mm)")
a1.set_ylabel("|U|, time mean (m/s)")
a2.set_xlabel("x along the vented leg (mm)")
a2.set_ylabel("U_x, time mean (m/s)")
for a in (a1, a2):
    a.grid(alpha=0.3)
    a.legend(fontsize=7)
fig.tight_layout()
fig.savefig(f"{out_dir}/stacks_air_path.png", dpi=90)
print(f"plots in {out_dir}")
