#!/usr/bin/env python3
"""Makes one variant of openfoam-cases/fluidised-bed in the working directory (issue 31: one
change at a time from the case as committed: until commit 2718228 at 0.66 m/s with frictionless
front and back walls, since then at 0.6 m/s with friction 0.1 on every wall). usage: make_variant.py NAME (see the branches below for the names)."""
import os, re, shutil, subprocess, sys
REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
name = sys.argv[1]
dst = os.path.abspath(name)
if os.path.exists(dst):
    sys.exit(f"{dst} exists")
# the tracked files only
files = subprocess.check_output(["git", "-C", REPO, "ls-files", "openfoam-cases/fluidised-bed"], text=True).split()
for f in files:
    rel = f[len("openfoam-cases/fluidised-bed/"):]
    os.makedirs(os.path.dirname(os.path.join(dst, rel)) or dst, exist_ok=True)
    shutil.copy(os.path.join(REPO, f), os.path.join(dst, rel))
os.makedirs(f"{dst}/DEM/post", exist_ok=True)
shutil.copy(f"{dst}/reference/packed.data", f"{dst}/DEM/post/packed.data")
cp = f"{dst}/CFD/constant/couplingProperties"
deck = f"{dst}/DEM/in.liggghts_run"
def sub(path, a, b, count=1):
    s = open(path).read()
    n = s.count(a)
    assert n >= 1, (path, a)
    s = s.replace(a, b) if count == 0 else s.replace(a, b, count)
    open(path, "w").write(s)
def mesh(ny, nx=12, nz=26):
    sub(f"{dst}/CFD/system/blockMeshDict", "(12 1 26)", f"({nx} {ny} {nz})")
    shutil.rmtree(f"{dst}/CFD/constant/polyMesh")
    env = dict(os.environ, WM_PROJECT_DIR="/usr/share/openfoam")
    subprocess.check_call(["bash", "-c", "source /usr/share/openfoam/etc/bashrc 2>/dev/null; blockMesh -case CFD > log.blockMesh 2>&1"], cwd=dst, env=env)
def drag(law, extra=""):
    sub(cp, "    BeetstraDrag\n", f"    {law}\n")
    sub(cp, "BeetstraDragProps", f"{law}Props")
    if extra:
        sub(cp, f"{law}Props\n{{\n", f"{law}Props\n{{\n{extra}")
# the study's runs end at 1.0 s (window 0.55 ... 1.0 s) unless named long (the case runs 3.0 s)
sub(f"{dst}/CFD/system/controlDict", "endTime         3.0;", "endTime         1.0;")
# denser particle dumps (every 0.01 s) for time-averaged voidage profiles; no effect on results
sub(deck, "dump            dmp all custom 20000", "dump            dmp all custom 4000")
def inlet(u):
    """The plateau's superficial velocity u (the ramp from u/100 over 0.1 s)."""
    path = f"{dst}/CFD/0/U"
    s = open(path).read()
    s, n1 = re.subn(r"\(0\.1 \(0 0 [0-9.]+\)\)", f"(0.1 (0 0 {u}))", s)
    s, n0 = re.subn(r"\(0\.0 \(0 0 [0-9.]+\)\)", f"(0.0 (0 0 {u/100}))", s)
    assert n1 == 1 and n0 == 1, path
    open(path, "w").write(s)
if name == "base":
    pass
elif name == "u06":
    inlet(0.6)
elif name == "u09":
    inlet(0.9)
elif name == "u09tall":   # 0.9 m/s in a column twice as tall (0.2496 m, 12 x 1 x 52 cells): no particle leaves
    inlet(0.9)
    sub(f"{dst}/CFD/system/blockMeshDict", "H   0.1248;", "H   0.2496;")
    mesh(1, 12, 52)
    sub(f"{dst}/DEM/post/packed.data", "1.2479999999999999e-01 zlo zhi", "2.4959999999999999e-01 zlo zhi")
elif name == "depth3":
    mesh(3)
elif name == "depth5":
    mesh(5)
elif name == "fine":   # cells halved across the width and along the height (24 x 1 x 52)
    mesh(1, 24, 52)
elif name == "yfric":   # front/back walls (type 2) with the particles' friction 0.1
    sub(deck, "coefficientFriction peratomtypepair 2 0.1 0.0 0.0 0.0", "coefficientFriction peratomtypepair 2 0.1 0.1 0.1 0.1")
elif name == "rest09":   # restitution 0.9 (particles and walls) instead of 0.986
    sub(deck, "coefficientRestitution peratomtypepair 2 0.986 0.986 0.986 0.986", "coefficientRestitution peratomtypepair 2 0.9 0.9 0.9 0.9")
elif name == "gidaspow":
    drag("GidaspowDrag", "    implForceDEM            true;\n")
elif name == "kochhill":
    drag("KochHillDrag")
elif name == "difelice":
    drag("DiFeliceDrag")
elif name == "exact":
    sub(cp, "voidFractionModel   divided;", "voidFractionModel   exact;   ")
    sub(cp, "dividedProps", "exactProps")
    sub(cp, "    scaleUpVol              1.0;\n", "")
elif name == "ci50":   # coupling every 50 DEM steps: the CFD step halves with it
    sub(cp, "couplingInterval    100;", "couplingInterval    50; ")
    sub(deck, "couple_every 100", "couple_every 50")
    sub(f"{dst}/CFD/system/controlDict", "deltaT          0.00025;", "deltaT          0.000125;")
elif name in ("long3", "yfric3", "u06long3", "u06yfric3"):   # the averaging window: to 3 s (window 1.0 ... 3.0 s)
    sub(f"{dst}/CFD/system/controlDict", "endTime         1.0;", "endTime         3.0;")
    if name in ("u06long3", "u06yfric3"):
        inlet(0.6)
    if name in ("yfric3", "u06yfric3"):
        sub(deck, "coefficientFriction peratomtypepair 2 0.1 0.0 0.0 0.0", "coefficientFriction peratomtypepair 2 0.1 0.1 0.1 0.1")
elif name == "count":   # the experiment's 0.03 m settled bed: drop the highest particles
    p = f"{dst}/DEM/post/packed.data"
    lines = open(p).read().split("\n")
    i0 = lines.index("Atoms") + 2
    i1 = i0
    while i1 < len(lines) and lines[i1].strip():
        i1 += 1
    atoms = lines[i0:i1]
    def top(l):
        w = l.split(); return float(w[6]) + float(w[2]) / 2
    keep = sorted(atoms, key=top)
    # the mean surface is measured by runner::Bed; scale the count by 0.03 / 0.03242
    n = round(len(atoms) * 0.03 / 0.03242)
    kept_ids = set(id(a) for a in keep[:n])
    atoms2 = [a for a in atoms if id(a) in kept_ids]
    ids = set(a.split()[0] for a in atoms2)
    out = []
    in_vel = False
    for l in lines[i1:]:
        if l.strip() == "Velocities":
            in_vel = True
        w = l.split()
        if in_vel and len(w) == 7 and w[0] not in ids:
            continue
        out.append(l)
    hdr = lines[:i0]
    hdr = [re.sub(r"^\d+ atoms", f"{len(atoms2)} atoms", l) for l in hdr]
    open(p, "w").write("\n".join(hdr + atoms2 + out))
    print("kept", len(atoms2), "of", len(atoms))
else:
    sys.exit(f"unknown variant {name}")
print("made", dst)
