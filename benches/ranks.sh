#!/usr/bin/env bash
# Scaling of the N-rank coupling (issue 15): a bed of NP spheres in a box, run as
# `mpirun -np N foamgrain run CASE --dem liggghts --fluid FLUID` for each N in RANKS, reporting
# per rank (postProcessing/ranks.csv: particles held, cells touched, bytes exchanged per
# coupling step, peak memory) and per run (time per coupling step, of which DEM / fluid /
# coupling), side by side in one table. A measurement, not a test: nothing here passes or fails
# but the runs themselves.
#
#   benches/ranks.sh [NP=100000] [RANKS="1 2 4"] [STEPS=5] [FLUID=native] [SOLVER_NP=1] [CELL=0.0025] [HEIGHT]
#
# CELL is the cells' side (m), HEIGHT the box's height (m; by default three times the bed's):
# `benches/ranks.sh 100000 "1 2 4 8" 3 native 1 0.001 0.1` meshes the box with 100 × 100 × 100 =
# 10⁶ cells. Each coupler rank other than 0 holds only its part of the mesh (`couple::part`),
# and with FLUID=openfoam on N > 1 ranks rank 0 too: the "cells held" column, and "cuts" (parts
# cut during the run; empty: the whole mesh).
# "mesh MiB" and "particles MiB" are what the rank's coupler and sides hold for its cells and
# its particles at the end (`couple::HeldBytes`, counted on the arrays; LIGGGHTS's own atom
# arrays are not counted), "rest MiB" the end memory less both (the program, LIGGGHTS, MPI,
# and on rank 0 the native fluid's fields).
#
# With FLUID=openfoam, grainPisoFoam runs on SOLVER_NP ranks of its own; on N > 1 coupler ranks
# each rank then exchanges its touched cells straight with the solver ranks owning them (the
# "solver kB" columns), on one it sends the solver whole fields.
#
# The bed is a simple cubic lattice (spacing 1.1 d, d = 1 mm, ρp 2000 kg/m³) written straight
# as a LIGGGHTS data file (no packing stage), in a 0.1 × 0.1 × H m box of cells of 2.5 d, with a
# uniform upward flow of 0.005 m/s through it; LIGGGHTS's ranks cut the box across its height
# (`processors * * 1`). Needs foamgrain built with `--features mpi,liggghts`, Debian's
# LIGGGHTS and OpenMPI (and grainPisoFoam for FLUID=openfoam). Writes the table to stdout and
# the runs to $OUT (a temporary directory unless set).
set -euo pipefail
cd "$(dirname "$0")/.."
np="${1:-100000}"
ranks="${2:-1 2 4}"
steps="${3:-5}"
fluid="${4:-native}"
solver_np="${5:-1}"
cell="${6:-0.0025}"
height="${7:-0}"
export WM_PROJECT_DIR=/usr/share/openfoam
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
fg="${CARGO_TARGET_DIR:-target}/release/foamgrain"
out="${OUT:-$(mktemp -d)}"
base="$out/base"
rm -rf "$base"
mkdir -p "$base/CFD/constant" "$base/CFD/system" "$base/CFD/0" "$base/DEM/post"
src=openfoam-cases/ergun/CFD
cp "$src"/system/{controlDict,fvSchemes,fvSolution} "$base/CFD/system/"
cp "$src"/constant/{couplingProperties,g,transportProperties} "$base/CFD/constant/"
cp "$src"/0/{p,Ksl,Us,f,voidfraction} "$base/CFD/0/"

python3 - "$base" "$np" "$steps" "$cell" "$height" <<'PY'
import math, sys
base, np_, steps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
cell, height = float(sys.argv[4]), float(sys.argv[5])
d, s, w = 1e-3, 1.1e-3, 0.1
nx = int(w / s)                       # lattice sites across
nz = math.ceil(np_ / nx**2)           # layers
h = height if height > 0 else max(3 * nz * s, 0.02)   # box height: bed in the lowest third
dx = cell
cx, cz = round(w / dx), round(h / dx)
h = cz * dx
header = "FoamFile { version 2.0; format ascii; class dictionary; object %s; }\n"
open(f"{base}/CFD/system/blockMeshDict", "w").write(header % "blockMeshDict" + f"""
vertices ((0 0 0) ({w} 0 0) ({w} {w} 0) (0 {w} 0) (0 0 {h}) ({w} 0 {h}) ({w} {w} {h}) (0 {w} {h}));
blocks (hex (0 1 2 3 4 5 6 7) ({cx} {cx} {cz}) simpleGrading (1 1 1));
boundary (
  inlet {{ type patch; faces ((0 3 2 1)); }}
  outlet {{ type patch; faces ((4 5 6 7)); }}
  wall {{ type wall; faces ((0 4 7 3) (2 6 5 1) (1 5 4 0) (3 7 6 2)); }}
);
""")
open(f"{base}/CFD/0/U", "w").write(header.replace("object %s;", "class volVectorField; object U;").replace("class dictionary; ", "") + """
dimensions [0 1 -1 0 0 0 0];
internalField uniform (0 0 0.005);
boundaryField {
  inlet { type fixedValue; value uniform (0 0 0.005); }
  outlet { type zeroGradient; }
  wall { type noSlip; }
}
""")
dt_c = 50 * 1e-5
cd = open(f"{base}/CFD/system/controlDict").read()
import re
cd = re.sub(r"endTime\s+[^;]+;", f"endTime {steps * dt_c};", cd)
cd = re.sub(r"writeInterval\s+[^;]+;", f"writeInterval {steps * dt_c};", cd)
open(f"{base}/CFD/system/controlDict", "w").write(cd)
lines = []
k = 0
for iz in range(nz):
    for iy in range(nx):
        for ix in range(nx):
            if k == np_:
                break
            k += 1
            lines.append(f"{k} 1 {d} 2000 {(ix + 0.5) * s} {(iy + 0.5) * s} {(iz + 0.5) * s}")
with open(f"{base}/DEM/post/packed.data", "w") as f:
    f.write(f"LIGGGHTS data file: {k} spheres on a lattice\n\n{k} atoms\n1 atom types\n\n")
    f.write(f"0 {w} xlo xhi\n0 {w} ylo yhi\n0 {h} zlo zhi\n\nAtoms\n\n")
    f.write("\n".join(lines) + "\n")
open(f"{base}/DEM/in.liggghts_run", "w").write(f"""# benches/ranks.sh: a lattice bed, coupled (the coupler issues the runs)
atom_style      granular
atom_modify     map array
communicate     single vel yes
boundary        f f f
newton          off
processors      * * 1
units           si
read_data       post/packed.data
neighbor        0.0002 bin
neigh_modify    delay 0
fix             m1 all property/global youngsModulus peratomtype 5.e6
fix             m2 all property/global poissonsRatio peratomtype 0.45
fix             m3 all property/global coefficientRestitution peratomtypepair 1 0.3
fix             m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style      gran model hertz tangential history
pair_coeff      * *
timestep        0.00001
fix             gravi all gravity 9.81 vector 0.0 0.0 -1.0
fix             zwall all wall/gran model hertz tangential history primitive type 1 zplane 0.0
fix             cfd all couple/cfd couple_every 50 mpi
fix             cfd2 all couple/cfd/force/implicit
fix             integr all nve/sphere
thermo_style    custom step atoms ke
thermo          1000
""")
print(f"lattice bed: {k} spheres, {nx} x {nx} x {nz}; mesh {cx} x {cx} x {cz} = {cx*cx*cz} cells", file=sys.stderr)
PY
(cd "$base/CFD" && blockMesh >log.blockMesh 2>&1)

rows=()
for n in $ranks; do
    run="$out/np$n"
    rm -rf "$run"
    cp -r "$base" "$run"
    echo "== $n rank(s)" >&2
    extra=()
    [ "$fluid" = openfoam ] && extra=(--np "$solver_np")
    mpirun -np "$n" "$fg" run "$run" --dem liggghts --fluid "$fluid" "${extra[@]}" >"$run.log" 2>&1 || true
    line=$(grep 'coupling steps to' "$run.log" || echo "")
    if [ -z "$line" ]; then
        echo "run on $n ranks failed; see $run.log" >&2
        tail -5 "$run.log" >&2
        exit 1
    fi
    rows+=("$n|$line|$run/postProcessing/ranks.csv")
done

python3 - "${rows[@]}" <<'PY'
import csv, re, sys
print("| ranks | loop s/step | DEM % | fluid % | coupling % | rank | particles | cells touched | cells held | cuts | kB sent/step | kB received/step | peak MiB | end MiB | mesh MiB | particles MiB | rest MiB | solver kB sent/step | solver kB received/step |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for row in sys.argv[1:]:
    n, line, path = row.split("|")
    m = re.search(r"(\d+) coupling steps.*coupled loop ([\d.]+) s: DEM ([\d.]+) % fluid ([\d.]+) % coupling ([\d.]+) %", line)
    steps, loop, dem, fl, cp = m.groups()
    per = float(loop) / int(steps)
    ranks = list(csv.DictReader(open(path)))
    for i, r in enumerate(ranks):
        head = f"| {n} | {per:.3f} | {dem} | {fl} | {cp} " if i == 0 else "| | | | | "
        kb = lambda x: f"{float(x) / 1e3:.1f}" if x else ""
        mesh, parts, end = r.get('mesh_mib', ''), r.get('particle_mib', ''), r.get('end_memory_mib', '')
        rest = f"{float(end) - float(mesh) - float(parts):.1f}" if mesh and parts and end else ""
        print(head + f"| {r['rank']} | {r['particles']} | {r['cells_touched']} | {r.get('cells_held', '')} | {r.get('mesh_cuts', '')} | {kb(r['bytes_sent_per_step'])} | {kb(r['bytes_received_per_step'])} | {r['peak_memory_mib']} | {end} | {mesh} | {parts} | {rest} | {kb(r.get('solver_bytes_sent_per_step'))} | {kb(r.get('solver_bytes_received_per_step'))} |")
PY
