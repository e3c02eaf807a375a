#!/usr/bin/env bash
# A million particles (issue 29): a scaled fluidised bed of NX³ spheres (10⁶ by default) in a
# mesh of ≥ 10⁵ cells, run for a few coupling steps on each stack, reporting per run the
# particle-steps per second of the coupled loop (particles × DEM steps / loop wall time), its
# DEM / fluid / coupling split, the peak memory and CPU time of every process of the run (from
# /proc, sampled every second: a process that waits without spinning takes little CPU), and the
# same DEM deck on Debian's LIGGGHTS alone for the same number of DEM steps. A measurement, not
# a test: nothing here passes or fails but the runs themselves.
#
#   benches/million.sh [STEPS=2] [RUNS="native cosim mpi-native liggghts liggghts-np2"] [NX=100]
#
# The runs (each in a copy of the generated case under $OUT):
#   native        foamgrain run CASE --np 2                        (native DEM and fluid, 2 threads)
#   cosim         foamgrain run CASE --dem liggghts --fluid openfoam --np 1
#                 (LIGGGHTS in-process, grainPisoFoam on one rank of its own)
#   cosim-np2     mpirun -np 2 foamgrain run CASE --dem liggghts --fluid openfoam --np 1
#   mpi-native    mpirun -np 2 foamgrain run CASE --dem liggghts   (native fluid on rank 0)
#   liggghts      liggghts -in in.liggghts_alone                   (the run deck without coupling)
#   liggghts-np2  mpirun -np 2 liggghts -in in.liggghts_alone
#
# The bed: NX × NX × NX spheres of the fluidised bed (openfoam-cases/fluidised-bed: d 1.2 mm,
# ρp 1000 kg/m³, its run deck with its walls moved to the column's: Hertz contact, friction 0.1,
# e 0.986, DEM step 2.5e-6 s) on a simple cubic lattice of spacing 1.05 d, written straight as
# a LIGGGHTS data file (no packing stage), in a square column of side NX · 1.05 d cut into
# cells of 3 d (3.6 mm), 2.4 times as high as the bed; air (the fluidised bed's
# transportProperties, fvSchemes, fvSolution, couplingProperties: model A, Beetstra drag, ∇p
# and viscous forces, `divided` voidage, a coupling step every 100 DEM steps = one CFD step of
# 2.5e-4 s) flows upward at U_IN m/s (0.6 unless set: the fluidised
# bed's plateau). NX=100: 10⁶ spheres, 35 × 35 × 84 = 102,900 cells.
#
# Needs foamgrain built with `--features mpi,liggghts` (release), Debian's LIGGGHTS and
# OpenMPI, grainPisoFoam (openfoam-cases/solver/build.sh) for cosim. Writes the table to
# stdout, the runs and their logs to $OUT (a temporary directory unless set; the generated case
# is reused when $OUT/base was made by this script with the same NX and U_IN).
set -euo pipefail
cd "$(dirname "$0")/.."
steps="${1:-2}"
runs="${2:-native cosim mpi-native liggghts liggghts-np2}"
nx="${3:-100}"
u_in="${U_IN:-0.6}"
export WM_PROJECT_DIR=/usr/share/openfoam
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
fg="$(realpath "${FOAMGRAIN:-${CARGO_TARGET_DIR:-target}/release/foamgrain}")"
out="${OUT:-$(mktemp -d)}"
base="$out/base"
interval=100 # DEM steps per coupling step (the fluidised bed's couplingInterval)

key="$nx $u_in $(sha1sum <"$0" | cut -c1-12)" # the case as this script makes it
if [ "$(cat "$base/key" 2>/dev/null)" != "$key" ]; then
    rm -rf "$base"
    mkdir -p "$base/CFD/constant" "$base/CFD/system" "$base/CFD/0" "$base/DEM/post"
    src=openfoam-cases/fluidised-bed/CFD
    cp "$src"/system/{controlDict,fvSchemes,fvSolution} "$base/CFD/system/"
    cp "$src"/constant/{couplingProperties,g,transportProperties,turbulenceProperties} "$base/CFD/constant/"
    cp "$src"/0/{p,Ksl,Us,f,voidfraction} "$base/CFD/0/"
    python3 - "$base" "$nx" "$u_in" <<'PY'
import math, re, sys
base, nx, u_in = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
d = 1.2e-3
s = 1.05 * d                   # lattice spacing
w = nx * s                     # column side
dx = 3 * d                     # cell edge
cx = max(1, round(w / dx))
cz = math.ceil(2.4 * cx)       # column 2.4 times the bed's height
h = cz * (w / cx)
header = "FoamFile { version 2.0; format ascii; class %s; object %s; }\n"
open(f"{base}/CFD/system/blockMeshDict", "w").write(header % ("dictionary", "blockMeshDict") + f"""
vertices ((0 0 0) ({w} 0 0) ({w} {w} 0) (0 {w} 0) (0 0 {h}) ({w} 0 {h}) ({w} {w} {h}) (0 {w} {h}));
blocks (hex (0 1 2 3 4 5 6 7) ({cx} {cx} {cz}) simpleGrading (1 1 1));
boundary (
  inlet {{ type patch; faces ((0 3 2 1)); }}
  outlet {{ type patch; faces ((4 5 6 7)); }}
  wall {{ type wall; faces ((0 4 7 3) (2 6 5 1) (1 5 4 0) (3 7 6 2)); }}
);
""")
open(f"{base}/CFD/0/U", "w").write(header % ("volVectorField", "U") + f"""
dimensions [0 1 -1 0 0 0 0];
internalField uniform (0 0 {u_in});
boundaryField {{
  inlet {{ type fixedValue; value uniform (0 0 {u_in}); }}
  outlet {{ type zeroGradient; }}
  wall {{ type slip; }}
}}
""")
with open(f"{base}/DEM/post/packed.data", "w") as f:
    n = nx ** 3
    f.write(f"LIGGGHTS data file: {n} spheres on a lattice\n\n{n} atoms\n2 atom types\n\n")
    f.write(f"0 {w} xlo xhi\n0 {w} ylo yhi\n0 {h} zlo zhi\n\nAtoms\n\n")
    k = 0
    for iz in range(nx):
        rows = []
        for iy in range(nx):
            for ix in range(nx):
                k += 1
                rows.append(f"{k} 1 {d} 1000 {(ix + 0.5) * s:.9g} {(iy + 0.5) * s:.9g} {(iz + 0.5) * s:.9g}\n")
        f.write("".join(rows))
# the fluidised bed's own run deck, its walls moved to the column's and its dump left out; the
# deck run alone loses the coupling fixes too (the bench appends its `run`)
deck = open("openfoam-cases/fluidised-bed/DEM/in.liggghts_run").read()
def sub(pattern, new, text):
    out, count = re.subn(pattern, new, text, flags=re.M)
    if count != 1:
        sys.exit(f"openfoam-cases/fluidised-bed/DEM/in.liggghts_run: no single line `{pattern}`")
    return out
deck = sub(r"(xplane) 0\.0432$", rf"\1 {w}", deck)
deck = sub(r"(yplane) 0\.01$", rf"\1 {w}", deck)
deck = sub(r"^dump .*\n", "", deck)
# on N ranks LIGGGHTS cuts the column across its width, not its height: cut at mid-height, the
# bed (the lowest 42 %) is all on rank 0 and rank 1 spins in LIGGGHTS's waits (docs/scaling.md)
deck = sub(r"^(newton +off\n)", r"\1processors      * * 1\n", deck)
intro = f"# benches/million.sh: a lattice bed of {n} spheres, "
open(f"{base}/DEM/in.liggghts_run", "w").write(intro + "coupled\n" + deck)
alone = sub(r"^fix +cfd all couple/cfd .*\n", "", deck)
alone = sub(r"^fix +cfd2 all couple/cfd/force/implicit.*\n", "", alone)
open(f"{base}/DEM/in.liggghts_alone", "w").write(intro + "alone\n" + alone)
print(f"lattice bed: {n} spheres, {nx}^3; mesh {cx} x {cx} x {cz} = {cx*cx*cz} cells, "
      f"column {w:.4f} x {w:.4f} x {h:.4f} m", file=sys.stderr)
PY
    (cd "$base/CFD" && blockMesh >log.blockMesh 2>&1)
    echo "$key" >"$base/key"
fi
dt=$(python3 -c "print($steps * 2.5e-4)")
sed -i -E "s/^endTime .*/endTime         $dt;/; s/^writeInterval .*/writeInterval   $dt;/" \
    "$base/CFD/system/controlDict"

# Samples every process whose command line names the run directory $1 once a second, until
# the file $2 exists: its peak resident memory (VmHWM) and CPU time (utime + stime). Writes one
# line per process to stdout: pid, name, seconds seen, CPU seconds, peak MiB.
sampler() {
    python3 - "$1" "$2" <<'PY'
import os, sys, time
run, stop = sys.argv[1], sys.argv[2]
tick = os.sysconf("SC_CLK_TCK")
seen = {}
while not os.path.exists(stop):
    now = time.time()
    for pid in os.listdir("/proc"):
        if not pid.isdigit() or int(pid) == os.getpid():
            continue
        try:
            cmd = open(f"/proc/{pid}/cmdline", "rb").read().replace(b"\0", b" ").decode()
            if run not in cmd or "python3" in cmd or "/usr/bin/time" in cmd:
                continue
            stat = open(f"/proc/{pid}/stat").read()
            fields = stat[stat.rindex(")") + 2:].split()
            cpu = (int(fields[11]) + int(fields[12])) / tick
            hwm = 0
            for line in open(f"/proc/{pid}/status"):
                if line.startswith("VmHWM:"):
                    hwm = int(line.split()[1]) / 1024
        except (OSError, ValueError, IndexError):
            continue
        name = os.path.basename(cmd.split()[0])
        first = seen.get(pid, (now,))[0]
        seen[pid] = (first, now, name, cpu, max(hwm, seen.get(pid, (0, 0, "", 0, 0))[4]))
    time.sleep(1)
for pid, (first, last, name, cpu, hwm) in sorted(seen.items(), key=lambda x: int(x[0])):
    print(f"{pid} {name} {last - first:.0f} {cpu:.1f} {hwm:.0f}")
PY
}

# Runs "$@" in the run directory $run with the sampler and /usr/bin/time; the logs go to $run.*.
measure() {
    rm -f "$run.stop"
    sampler "$run" "$run.stop" >"$run.procs" &
    local sp=$!
    local load
    load=$(cut -d' ' -f1-3 /proc/loadavg)
    /usr/bin/time -v "$@" >"$run.log" 2>&1 || echo "exit status $? (see $run.log)" >&2
    touch "$run.stop"
    wait "$sp"
    echo "$load" >"$run.load"
}

rows=()
for r in $runs; do
    run="$out/$r"
    rm -rf "$run"
    cp -r "$base" "$run"
    echo "== $r (load $(cut -d' ' -f1-3 /proc/loadavg))" >&2
    case "$r" in
        native) measure "$fg" run "$run" --np 2 ;;
        cosim) measure "$fg" run "$run" --dem liggghts --fluid openfoam --np 1 ;;
        cosim-np2) measure mpirun -np 2 "$fg" run "$run" --dem liggghts --fluid openfoam --np 1 ;;
        mpi-native) measure mpirun -np 2 "$fg" run "$run" --dem liggghts --fluid native ;;
        liggghts | liggghts-np2)
            echo "run $((steps * interval))" >>"$run/DEM/in.liggghts_alone"
            launcher=()
            [ "$r" = liggghts-np2 ] && launcher=(mpirun -np 2)
            (cd "$run/DEM" && measure "${launcher[@]}" liggghts -in "$run/DEM/in.liggghts_alone") ;;
        *) echo "unknown run $r" >&2; exit 1 ;;
    esac
    rows+=("$r|$run")
done

python3 - "$interval" "${rows[@]}" <<'PY'
import re, sys
interval = int(sys.argv[1])
print("| run | particles | cells | coupling steps | DEM steps | loop s | particle-steps/s | DEM % | fluid % | coupling % | output % | peak MiB per process | CPU s / wall s per process | load (1, 5, 15 min) |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for row in sys.argv[2:]:
    name, run = row.split("|")
    log = open(run + ".log").read()
    load = open(run + ".load").read().strip().replace(" ", ", ")
    procs = [l.split() for l in open(run + ".procs") if l.strip()]
    mem = ", ".join(f"{p[1]} {p[4]}" for p in procs if p[1] != "orted")
    cpu = ", ".join(f"{p[1]} {p[3]}/{p[2]}" for p in procs if p[1] != "orted")
    m = re.search(r"(\d+) coupling steps to t = \S+ s, (\d+) particles at the end, (\d+) cells;.*coupled loop ([\d.]+) s: DEM ([\d.]+) % fluid ([\d.]+) % coupling ([\d.]+) % output ([\d.]+) %", log)
    if m:
        steps, parts, cells, loop, dem, fl, cp, outp = m.groups()
        dem_steps = int(steps) * interval
        rate = int(parts) * dem_steps / float(loop)
        print(f"| {name} | {parts} | {cells} | {steps} | {dem_steps} | {loop} | {rate:.3g} | {dem} | {fl} | {cp} | {outp} | {mem} | {cpu} | {load} |")
        continue
    m = re.search(r"Loop time of ([\d.e+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
    if m:
        loop, procs_n, dem_steps, parts = m.groups()
        rate = int(parts) * int(dem_steps) / float(loop)
        print(f"| {name} | {parts} | | | {dem_steps} | {float(loop):.1f} | {rate:.3g} | 100 | | | | {mem} | {cpu} | {load} |")
        continue
    print(f"| {name} | run failed: see {run}.log | | | | | | | | | | {mem} | {cpu} | {load} |")
PY
