#!/usr/bin/env python3
"""One row per run of the full conveyor (issue 30): what its `postProcessing/integrals.csv`
says about the particles in the downstream tube and where they went.

    benches/conveyor-study/table.py RUN [RUN …]

Columns (times in s, velocities in m/s):
  first_tube   the first time a particle is in the downstream tube (z from tubeFrom to tubeTo)
  tube_v       the particles' mean axial velocity in the tube, over every sample (coupling step)
               weighted by the particles in it: the case's reported figure
  tube_v_med   the median over the steps with particles in the tube of the step's mean
  first_sec    the first time a particle is in the secondary chamber
  out/vent/sec/rest  at the run's end: out through the vented outlet (cumulative), in the vented
               leg, in the secondary chamber, elsewhere in the system
  air_out      the vented outlet's mean air velocity over t >= 0.01 s
An empty cell is a figure the run does not have (no particle reached that part), never 0.
"""
import csv
import statistics
import sys


def row(run):
    rows = list(csv.DictReader(open(f"{run}/postProcessing/integrals.csv")))
    f = lambda r, k: float(r[k]) if r[k] not in ("", "nan") else None
    t = [float(r["time"]) for r in rows]
    n_tube = [f(r, "tube_particles") or 0 for r in rows]
    v_tube = [f(r, "tube_axial_velocity") for r in rows]
    samples = [(n, v) for n, v in zip(n_tube, v_tube) if n > 0 and v is not None]
    first = lambda col: next((ti for ti, r in zip(t, rows) if (f(r, col) or 0) > 0), None)
    air = [f(r, "outlet_velocity") for ti, r in zip(t, rows) if ti >= 0.01]
    air = [a for a in air if a is not None]
    last = rows[-1]
    out = sum(int(float(r["particles_out"])) for r in rows)
    held = int(float(last["particles"]))
    vent = int(float(last["vent_leg_particles"] or 0))
    sec = int(float(last["secondary_particles"] or 0))
    return {
        "run": run,
        "end": t[-1],
        "first_tube": first("tube_particles"),
        "tube_v": sum(n * v for n, v in samples) / sum(n for n, _ in samples) if samples else None,
        "tube_v_med": statistics.median(v for _, v in samples) if samples else None,
        "first_sec": first("secondary_particles"),
        "out": out,
        "vent": vent,
        "sec": sec,
        "rest": held - vent - sec,
        "air_out": sum(air) / len(air) if air else None,
    }


def cell(v):
    if v is None:
        return ""
    return f"{v:.4g}" if isinstance(v, float) else str(v)


keys = ["run", "end", "first_tube", "tube_v", "tube_v_med", "first_sec", "out", "vent", "sec",
        "rest", "air_out"]
print("| " + " | ".join(keys) + " |")
print("|" + "---|" * len(keys))
for run in sys.argv[1:]:
    r = row(run)
    print("| " + " | ".join(cell(r[k]) for k in keys) + " |")
