#!/usr/bin/env bash
# Issue 17 target 5: grainPisoFoam's advance overlapped with the next DEM interval (the default
# of `foamgrain run --fluid openfoam`) against the sequential order (`--no-overlap`), on the
# Ergun reference case (openfoam-cases/ergun) shortened to END_TIME, with the native DEM and with
# LIGGGHTS in-process. Prints per run the wall time of the coupled loop and the split the run
# reports (DEM / fluid / coupling / output; with the overlap "fluid" is what the coupler spends
# starting the solver's advance and waiting for it), the solver's exchange line, and whether
# integrals.csv is the same byte for byte in both orders. A measurement, not a test.
#
#   benches/overlap.sh [END_TIME=0.025] [REPEAT=2] [DEMS="native liggghts"] [NP=10000]
#
# The bed is packed once (LIGGGHTS binary, `-var np NP`) and copied into every run, so all runs
# start from the same particles. The orders alternate (overlap, sequential, overlap, …) so that
# a change in the machine's load hits both. Needs foamgrain built with
# `cargo build --release -p cli --features mpi,liggghts`, grainPisoFoam
# (openfoam-cases/solver/build.sh; FOAMGRAIN_CACHE as for `foamgrain run`), Debian's LIGGGHTS
# and OpenMPI. The runs go to $OUT (a temporary directory unless set).
set -euo pipefail
cd "$(dirname "$0")/.."
end="${1:-0.025}"
repeat="${2:-2}"
dems="${3:-native liggghts}"
np="${4:-10000}"
export WM_PROJECT_DIR=/usr/share/openfoam
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
fg="$(realpath "${CARGO_TARGET_DIR:-target}/release/foamgrain")"
out="${OUT:-$(mktemp -d)}"
mkdir -p "$out"

pack="$out/packed.data"
if [ ! -f "$pack" ]; then
    .ci/copy-case openfoam-cases/ergun "$out/pack"
    # one coupling step after the packing (its checks fail so early: only the pack is kept)
    "$fg" run "$out/pack" --fluid native --dem liggghts --var "np=$np" --end-time 0.0005 \
        >"$out/pack.log" 2>&1 || true
    cp "$out/pack/DEM/post/packed.data" "$pack"
fi

printf '%-9s %-11s %4s %8s %7s %7s %9s %7s %9s %s\n' dem order run "loop s" "DEM %" "fluid %" \
    "coupl. %" "out %" "transfer" "solver waits (ms/interval)"
for dem in $dems; do
    for r in $(seq 1 "$repeat"); do
        for order in overlap sequential; do
            name="$dem-$order-$r"
            rm -rf "${out:?}/$name"
            .ci/copy-case openfoam-cases/ergun "$out/$name"
            mkdir -p "$out/$name/DEM/post"
            cp "$pack" "$out/$name/DEM/post/packed.data"
            flag=()
            [ "$order" = sequential ] && flag=(--no-overlap)
            "$fg" run "$out/$name" --fluid openfoam --dem "$dem" --end-time "$end" "${flag[@]}" \
                >"$out/$name.log" 2>&1 || true
            python3 - "$out/$name.log" "$dem" "$order" "$r" <<'PY'
import re, sys
log, dem, order, r = sys.argv[1:]
text = open(log, errors="replace").read()
m = re.search(r"coupled loop ([\d.]+) s: DEM ([\d.]+) % fluid ([\d.]+) % coupling ([\d.]+) % "
              r"output ([\d.]+) %", text)
w = re.search(r"([\d.]+) ms transfer, ([\d.]+) ms waiting for the solver", text)
if not m:
    print(f"{dem:9} {order:11} {r:>4}  failed: see {log}")
else:
    print(f"{dem:9} {order:11} {r:>4} {m[1]:>8} {m[2]:>7} {m[3]:>7} {m[4]:>9} {m[5]:>7} "
          f"{w[1] if w else '?':>9} {w[2] if w else '?'}")
PY
        done
        a="$out/$dem-overlap-$r/postProcessing/integrals.csv"
        b="$out/$dem-sequential-$r/postProcessing/integrals.csv"
        if cmp -s "$a" "$b"; then
            echo "$dem run $r: integrals.csv identical in both orders"
        else
            echo "$dem run $r: integrals.csv DIFFERS between the orders"
        fi
    done
done
echo "runs in $out; load average now: $(cut -d' ' -f1-3 /proc/loadavg)"
