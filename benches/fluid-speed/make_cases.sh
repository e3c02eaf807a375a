#!/usr/bin/env bash
# The two ≥ 10⁵-cell cases of the native-fluid speed benchmark (issue 29, item 4), both made
# from OpenFOAM's own pisoFoam/RAS/cavity example as Debian ships it (package
# openfoam-examples), so that Debian's pisoFoam runs them unchanged:
#
#   cavity320  the example refined to 320 × 320 × 1 cells (102 400), 2-D as shipped; deltaT
#              scaled with the cell size (0.005 · 20/320 → 2.5e-4 s, Courant number < 1).
#   cavity3d   the same lid-driven cavity extruded to a cube, 48 × 48 × 48 cells (110 592):
#              the example's front and back become no-slip walls (part of `fixedWalls`, with
#              its wall functions), deltaT 0.005 · 20/48 → 1.5e-3 s. A 3-D k-ε case.
#
# Everything else — fvSchemes (limitedLinearV/limitedLinear), fvSolution (p: GAMG with a
# Gauss–Seidel smoother, tolerance 1e-6, relTol 0.1, pFinal relTol 0; U, k, ε: smoothSolver
# Gauss–Seidel, tolerance 1e-5), transport and turbulence properties — is the example's.
# endTime is short (STEPS steps of each), so a serial pisoFoam run takes about a minute or two
# on this machine; writeInterval makes endTime the only write.
#
#   benches/fluid-speed/make_cases.sh [OUT=/tmp/foamgrain-fluid-speed] [STEPS2D=100] [STEPS3D=100]
set -euo pipefail
out="${1:-/tmp/foamgrain-fluid-speed}"
steps2d="${2:-100}"
steps3d="${3:-100}"
ex=/usr/share/doc/openfoam-examples/examples/incompressible/pisoFoam/RAS/cavity
export WM_PROJECT_DIR=/usr/share/openfoam
blockmesh="$(command -v blockMesh || echo /usr/lib/openfoam/openfoam1912/platforms/linux64GccDPInt32Opt/bin/blockMesh)"
mkdir -p "$out"

# make NAME CELLS DT STEPS DEPTH THREED
make() {
    local c="$out/$1"
    rm -rf "$c"
    cp -r "$ex" "$c"
    chmod -R u+w "$c"
    rm -f "$c"/0/{nuTilda,omega}
    python3 - "$c" "$2" "$3" "$4" "$5" "$6" <<'PY'
import re, sys, pathlib
c, cells, dt, steps, depth, three_d = sys.argv[1:]
c = pathlib.Path(c)
bm = c / "system/blockMeshDict"
t = bm.read_text()
t = t.replace("(20 20 1)", f"({cells})")
# the cube's depth: the vertices' z (0.1 in the example, a thin 2-D slab)
t = re.sub(r"\((\d) (\d) 0\.1\)", lambda m: f"({m.group(1)} {m.group(2)} {depth})", t)
if three_d == "1":
    # front and back join fixedWalls; the empty patch goes
    t = t.replace("            (1 5 4 0)\n", "            (1 5 4 0)\n            (0 3 2 1)\n            (4 5 6 7)\n")
    t = re.sub(r"\n    frontAndBack\n    \{.*?\n    \}\n", "\n", t, flags=re.S)
    for f in (c / "0").iterdir():
        ft = f.read_text()
        ft = re.sub(r"\n    frontAndBack\n    \{.*?\n    \}\n", "\n", ft, flags=re.S)
        f.write_text(ft)
bm.write_text(t)
cd = c / "system/controlDict"
t = cd.read_text()
end = float(dt) * int(steps)
t = re.sub(r"\nendTime\s+[^;]*;", f"\nendTime         {end:g};", t)
t = re.sub(r"\ndeltaT\s+[^;]*;", f"\ndeltaT          {dt};", t)
t = re.sub(r"\nwriteInterval\s+[^;]*;", f"\nwriteInterval   {steps};", t)
t = re.sub(r"\nwritePrecision\s+[^;]*;", "\nwritePrecision  12;", t)
cd.write_text(t)
PY
    (cd "$c" && "$blockmesh" > log.blockMesh)
    echo "$c: $(grep -m1 'nCells' "$c/log.blockMesh" | tr -s ' ')"
}

make cavity320 "320 320 1" 2.5e-4 "$steps2d" 0.1 0
make cavity3d "48 48 48" 1.5e-3 "$steps3d" 1 1
