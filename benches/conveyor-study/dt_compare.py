#!/usr/bin/env python3
"""The seed's time-step study on the reduced conveyor (issue 30 item 3): the transient pressure
of runs at different fluid steps, from their `path` probes (CFD/postProcessing/path/0/p, the
reduced case's controlDict), compared with the first run given (the reference, e.g. Δt 5e-6 s).

    benches/conveyor-study/dt_compare.py REF_RUN RUN [RUN …]

The seed (Madden 2020, "Convergence Study 2/2", Fig. 6): dt 1e-4 against 5e-6 s, "very similar
qualitative results, with only minor variations (<5-10%) as the bulk particle mass moved out of
the initial annulus". Its figure shows pressure fields, not a number; the quantities here are
ours (kinematic pressure, m²/s²):
  p_floor  p at the annulus floor (probe 0, z 1 mm): what the inlet's total pressure leaves
           after the annulus air's dynamic head;
  dp_tube  p at the plenum's centre (probe 4, above the tube's entry) − p 1 mm before the
           outlet (probe 7): the tube's entry loss and friction, which the particles in the
           tube add to.
(The annulus's own gradient, probe 0 − probe 2, is about 10 m²/s² and of either sign: the bed
of 2000 spheres weighs 1.5 Pa over the annulus, less than the air's fluctuations. The tube's
static pressure between z 30 and 64 mm is small and of either sign too: its entry's vena
contracta.)
Each run's series is sampled at the reference run's times (linear interpolation); printed:
the values at the seed's frames 0.05, 0.08, 0.125 s, and over t = 0.01 … end the largest
and the mean |run − ref| / |ref mean over the window|.
"""
import sys


def probes(run):
    path = f"{run}/CFD/postProcessing/path/0/p"
    t, rows = [], []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        v = [float(x) for x in line.split()]
        t.append(v[0])
        rows.append(v[1:])
    return t, rows


def series(run):
    t, rows = probes(run)
    return t, {"p_floor": [r[0] for r in rows], "dp_tube": [r[4] - r[7] for r in rows]}


def at(t, y, x):
    """y(x) by linear interpolation in the sorted times t (None outside)."""
    if x < t[0] - 1e-12 or x > t[-1] + 1e-12:
        return None
    lo, hi = 0, len(t) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if t[mid] <= x:
            lo = mid
        else:
            hi = mid
    if t[hi] == t[lo]:
        return y[lo]
    w = (x - t[lo]) / (t[hi] - t[lo])
    return y[lo] + w * (y[hi] - y[lo])


ref_run, runs = sys.argv[1], sys.argv[2:]
tr, ref = series(ref_run)
grid = [x for x in tr if x >= 0.01]
for q in ("p_floor", "dp_tube"):
    window = [at(tr, ref[q], x) for x in grid]
    scale = abs(sum(window) / len(window))
    print(f"\n{q} (m²/s²); differences relative to the reference's mean over "
          f"{grid[0]:g} … {grid[-1]:g} s ({scale:.1f})")
    print("| run | 0.05 s | 0.08 s | 0.125 s | largest difference | mean difference |")
    print("|---|---|---|---|---|---|")
    for run in [ref_run] + runs:
        t, s = series(run)
        frames = [at(t, s[q], x) for x in (0.05, 0.08, 0.125)]
        diffs = [abs(at(t, s[q], x) - r) for x, r in zip(grid, window) if at(t, s[q], x) is not None]
        cell = lambda v: "" if v is None else f"{v:.1f}"
        if run == ref_run:
            big = mean = ""
        else:
            big = f"{100 * max(diffs) / scale:.1f} %" if diffs else ""
            mean = f"{100 * sum(diffs) / len(diffs) / scale:.2f} %" if diffs else ""
        print(f"| {run} | " + " | ".join(cell(v) for v in frames) + f" | {big} | {mean} |")
