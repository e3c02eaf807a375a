#!/usr/bin/env python3
"""Issue 31: one fluidised-bed run's figures over an averaging window.

usage: analyse.py RUN_DIR [t0 t1 [block]]   (default window 0.55 ... 1.0 s; block: the length of
the blocks whose means give the standard errors, default 0.5 s)

From postProcessing/integrals.csv (the run's own per-step samples): the mean surface height
(runner::Bed::height: mean over 2d bins of the highest particle top), its standard deviation,
Δp against the bed's weight, the expansion ratio against the height at t = 0.
From the particle dumps DEM/post/dump*.run inside the window (every 0.01 s): other height
measures — the 99th percentile of particle tops; the height where the slab-averaged solid
fraction (exact sphere–slab volumes, slabs of 1 mm) first falls below 0.1 and below half of
its mean over 5–15 mm — and the width-averaged voidage at z = 16.4 and 31.2 mm (a 2 mm slab),
the heights of Müller et al.'s MR profiles.
"""
import csv, glob, math, os, sys

run = sys.argv[1]
t0, t1 = (float(sys.argv[2]), float(sys.argv[3])) if len(sys.argv) > 3 else (0.55, 1.0)
block = float(sys.argv[4]) if len(sys.argv) > 4 else 0.5
W, T = 0.0432, 0.01
A = W * T

rows = list(csv.DictReader(open(os.path.join(run, "postProcessing/integrals.csv"))))
def col(name, pred):
    return [float(r[name]) for r in rows if r[name] != "" and pred(float(r["time"]))]
h = col("bed_height", lambda t: t0 <= t <= t1)
dp = col("pressure_drop", lambda t: t0 <= t <= t1)
wt = col("weight_per_area", lambda t: t0 <= t <= t1)
h_init = float(rows[0]["bed_height"])
mean = lambda v: sum(v) / len(v)
hm = mean(h)
hs = math.sqrt(mean([(x - hm) ** 2 for x in h]))
def block_se(pairs):
    """Standard error of the mean from the means of consecutive blocks of `block` s."""
    nb = int((t1 - t0) / block + 1e-9)
    if nb < 2:
        return float("nan")
    means = []
    for b in range(nb):
        v = [x for t, x in pairs if t0 + b * block < t <= t0 + (b + 1) * block]
        if v:
            means.append(sum(v) / len(v))
    m = sum(means) / len(means)
    return math.sqrt(sum((x - m) ** 2 for x in means) / (len(means) - 1) / len(means))
h_pairs = [(float(r["time"]), float(r["bed_height"])) for r in rows
           if r["bed_height"] != "" and t0 <= float(r["time"]) <= t1]
out = {
    "window": f"{t0}-{t1}", "samples": len(h), "h_initial": h_init, "h_mean": hm, "h_std": hs,
    "h_mean_stderr(blocks)": block_se(h_pairs), "expansion": hm / h_init, "dp_over_weight": mean(dp) / mean(wt), "particles": rows[-1]["particles"],
}

def slab_volume(r, zc, a, b):
    """Volume of a sphere (radius r, centre height zc) between z = a and z = b."""
    def cap_below(z):  # volume of the sphere below height z
        s = max(-r, min(r, z - zc))
        return math.pi * (r * r * (s + r) - ((s ** 3) + r ** 3) / 3.0)
    return cap_below(b) - cap_below(a)

dumps = []
for f in glob.glob(os.path.join(run, "DEM/post/dump*.run")):
    lines = open(f).read().split("\n")
    t_step = int(lines[1])
    dumps.append((t_step, f, lines))
dumps.sort()
dt_dem = 2.5e-6
tops99, h01, hhalf = [], [], []
phi_sum = [0.0] * 125
prof = {0.0164: [0.0] * 22, 0.0312: [0.0] * 22}
inner_series = {0.0164: [], 0.0312: []}   # (t, width mean of the inner 20 bins) per dump
nd = 0
for step, f, lines in dumps:
    t = step * dt_dem
    if not (t0 <= t <= t1):
        continue
    i = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    parts = [l.split() for l in lines[i:] if l.strip()]
    xs = [float(p[2]) for p in parts]; zs = [float(p[4]) for p in parts]; rs = [float(p[11]) for p in parts]
    tops = sorted(z + r for z, r in zip(zs, rs))
    tops99.append(tops[int(0.99 * (len(tops) - 1))])
    # solid fraction in 1 mm slabs
    nz = 125
    phi = [0.0] * nz
    for z, r in zip(zs, rs):
        k0, k1 = max(0, int((z - r) / 0.001)), min(nz - 1, int((z + r) / 0.001))
        for k in range(k0, k1 + 1):
            phi[k] += slab_volume(r, z, k * 0.001, (k + 1) * 0.001) / (A * 0.001)
    phi_sum = [a + b for a, b in zip(phi_sum, phi)]
    dense = mean(phi[5:15])
    h01.append(next(((k + 0.5) * 0.001 for k in range(nz) if k > 5 and phi[k] < 0.1), float("nan")))
    hhalf.append(next(((k + 0.5) * 0.001 for k in range(nz) if k > 5 and phi[k] < dense / 2), float("nan")))
    for zc in prof:
        a, b = zc - 0.001, zc + 0.001
        one = [0.0] * 22
        for x, z, r in zip(xs, zs, rs):
            if z + r > a and z - r < b:
                j = min(21, max(0, int(x / (W / 22))))
                one[j] += slab_volume(r, z, a, b) / ((W / 22) * T * 0.002)
        prof[zc] = [p + o for p, o in zip(prof[zc], one)]
        inner_series[zc].append((t, 1 - mean(one[1:21])))
    nd += 1
if nd:
    out.update({"dumps": nd, "h_top99": mean(tops99), "h_phi0.1": mean(h01), "h_half_phi": mean(hhalf)})
    # the same heights from the time-averaged solid-fraction profile (the experiment's kind of
    # quantity: a time-averaged voidage), rather than averaged per snapshot
    pa = [v / nd for v in phi_sum]
    dense = mean(pa[5:15])
    out["avg_profile: phi(5-15mm)"] = dense
    out["avg_profile: h(phi<0.1)"] = next(((k + 0.5) * 0.001 for k in range(125) if k > 5 and pa[k] < 0.1), float("nan"))
    out["avg_profile: h(phi<phi_bed/2)"] = next(((k + 0.5) * 0.001 for k in range(125) if k > 5 and pa[k] < dense / 2), float("nan"))
    out["avg_profile: solids height"] = sum(pa) * 0.001
    for zc, p in prof.items():
        eps = [1 - v / nd for v in p]
        out[f"eps_mean@{zc*1000:.1f}mm"] = mean(eps)
        out[f"eps_wall/centre@{zc*1000:.1f}mm"] = f"{(eps[0]+eps[-1])/2:.3f}/{max(eps):.3f}"
        out[f"eps_inner20@{zc*1000:.1f}mm"] = mean(eps[1:21])
        out[f"eps_inner20@{zc*1000:.1f}mm stderr(blocks)"] = block_se(inner_series[zc])
for k, v in out.items():
    print(f"{k:24s} {v:.5g}" if isinstance(v, float) else f"{k:24s} {v}")
