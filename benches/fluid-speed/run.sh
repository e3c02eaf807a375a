#!/usr/bin/env bash
# The native fluid against serial pisoFoam (issue 29, item 4), side by side on the cases of
# make_cases.sh: for each case, PAIRS interleaved pairs (pisoFoam, then `foamgrain fluid
# --np NP`, then pisoFoam again, …) so that both sides meet the same load, each run's wall
# time, the ratio native/pisoFoam pair by pair (min / median / max), the linear solvers'
# iterations per equation over the run from both logs, and the largest difference of the
# final fields (U, p, k, epsilon, nut at endTime) relative to pisoFoam's largest magnitude.
# A measurement, not a test: nothing here passes or fails but the runs themselves.
#
#   benches/fluid-speed/run.sh [PAIRS=3] [NP=2] [CASES="cavity320 cavity3d"]
#
# Needs Debian's OpenFOAM (pisoFoam, blockMesh) and a release build of foamgrain
# (`cargo build --release -p cli`; $FOAMGRAIN overrides its path). The cases are made in
# $OUT (default /tmp/foamgrain-fluid-speed) when missing; the runs go to $OUT/runs.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
pairs="${1:-3}"
np="${2:-2}"
cases="${3:-cavity320 cavity3d}"
out="${OUT:-/tmp/foamgrain-fluid-speed}"
fg="${FOAMGRAIN:-${CARGO_TARGET_DIR:-$here/../../target}/release/foamgrain}"
export WM_PROJECT_DIR=/usr/share/openfoam
[ -x "$fg" ] || { echo "no foamgrain at $fg (cargo build --release -p cli)" >&2; exit 1; }
for c in $cases; do
    [ -d "$out/$c/constant/polyMesh" ] || "$here/make_cases.sh" "$out"
done
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores; $(date -u '+%F %T') UTC"

# wall seconds of one command (its output to LOG)
timed() {
    local log="$1"; shift
    local t0 t1
    t0=$(date +%s.%N)
    "$@" > "$log" 2>&1
    t1=$(date +%s.%N)
    python3 -c "print(f'{$t1 - $t0:.2f}')"
}

for c in $cases; do
    piso="$out/runs/$c-pisoFoam"
    ours="$out/runs/$c-native"
    mkdir -p "$out/runs"
    for d in "$piso" "$ours"; do
        rm -rf "$d"
        cp -r "$out/$c" "$d"
    done
    end=$(sed -n 's/^endTime *\([^;]*\);/\1/p' "$out/$c/system/controlDict")
    times_p=()
    times_n=()
    for i in $(seq 1 "$pairs"); do
        times_p+=("$(cd "$piso" && timed log.pisoFoam pisoFoam)")
        times_n+=("$(timed "$ours/log.native" "$fg" fluid "$ours" --np "$np" --log)")
        echo "$c pair $i: pisoFoam ${times_p[-1]} s, native --np $np ${times_n[-1]} s (load $(cut -d' ' -f1 /proc/loadavg))"
    done
    echo "## $c ($(grep -m1 nCells "$out/$c/log.blockMesh" | tr -s ' '), endTime $end)"
    python3 - "${times_p[*]}" "${times_n[*]}" <<'PY'
import statistics, sys
p = [float(x) for x in sys.argv[1].split()]
n = [float(x) for x in sys.argv[2].split()]
r = [b / a for a, b in zip(p, n)]
f = lambda v: f"{min(v):.3g} / {statistics.median(v):.3g} / {max(v):.3g}"
print(f"wall s, min / median / max: pisoFoam {f(p)}; native {f(n)}")
print(f"ratio native/pisoFoam per pair, min / median / max: {f(r)}")
PY
    echo "linear-solver iterations over the run, pisoFoam:"
    "$here/compare.py" iters "$piso/log.pisoFoam"
    echo "native:"
    "$here/compare.py" iters "$ours/log.native"
    echo "final fields against pisoFoam's at t = $end:"
    "$here/compare.py" fields "$ours" "$piso" "$end"
done
