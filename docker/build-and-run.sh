#!/usr/bin/env bash
# foamgrain on Debian bookworm, step by step: the steps docker/Dockerfile runs, one RUN per
# step, so the image and a plain machine (as root) build and run the same way.
#
#   docker/build-and-run.sh              all steps in order
#   docker/build-and-run.sh STEP...      only these steps
#
# Steps:
#   packages   apt packages: OpenFOAM v1912 (openfoam, libopenfoam), OpenMPI, g++, dpkg-dev,
#              bzip2, curl and ca-certificates (for rustup), git, python3
#   rust       Rust stable through rustup, unless cargo is already on PATH
#   solver     grainPisoFoam with openfoam-cases/solver/build.sh (headers from Debian's
#              openfoam source package; idempotent)
#   foamgrain  cargo build --release -p cli (the foamgrain binary)
#   case       the Ergun reference case's CFD part (openfoam-cases/ergun/CFD, 4480 cells):
#              voidage of the committed LIGGGHTS pack with `foamgrain voidage`, then
#              grainPisoFoam on 2 MPI ranks for 20 steps of 5e-4 s with that voidage (prescribed,
#              no particle drag: the coupled run needs the coupler's MPI link, issue 8 item 2),
#              reconstructPar, and `foamgrain convert case` of the result to VTK
#
# Environment: FOAMGRAIN_RUN_DIR (case copy, default ${TMPDIR:-/tmp}/foamgrain-ergun),
# FOAMGRAIN_CACHE (solver build cache, see build.sh), CARGO_TARGET_DIR (cargo's usual meaning).
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
cd "$repo"

export WM_PROJECT_DIR=/usr/share/openfoam
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_mpi_yield_when_idle=1
export PATH="$HOME/.cargo/bin:$PATH"

step() { printf '\n==== %s (%s)\n' "$*" "$(date -u +%H:%M:%S)"; }

step_packages() {
    step "packages"
    local pkgs=(openfoam libopenfoam openmpi-bin libopenmpi-dev g++ dpkg-dev bzip2 curl
                ca-certificates git python3)
    local missing=()
    for p in "${pkgs[@]}"; do
        [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" = "install ok installed" ] \
            || missing+=("$p")
    done
    if [ "${#missing[@]}" -eq 0 ]; then
        echo "all present: ${pkgs[*]}"
        return
    fi
    echo "installing: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

step_rust() {
    step "rust"
    if command -v cargo >/dev/null; then
        cargo --version
        return
    fi
    curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs \
        | sh -s -- -y --profile minimal --default-toolchain stable
    cargo --version
}

step_solver() {
    step "solver: openfoam-cases/solver/build.sh"
    bash openfoam-cases/solver/build.sh
}

target_dir() {
    cargo metadata --format-version 1 --no-deps \
        | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])'
}

step_foamgrain() {
    step "foamgrain: cargo build --release -p cli"
    cargo build --release -p cli
    echo "foamgrain=$(target_dir)/release/foamgrain"
}

step_case() {
    step "case: openfoam-cases/ergun/CFD with grainPisoFoam on 2 ranks"
    local solver fg run
    solver="$(bash openfoam-cases/solver/build.sh 2>/dev/null | sed -n 's/^grainPisoFoam=//p')"
    fg="$(target_dir)/release/foamgrain"
    [ -x "$solver" ] || { echo "no grainPisoFoam: run the solver step" >&2; exit 1; }
    [ -x "$fg" ] || { echo "no $fg: run the foamgrain step" >&2; exit 1; }
    run="${FOAMGRAIN_RUN_DIR:-${TMPDIR:-/tmp}/foamgrain-ergun}"
    rm -rf "$run"
    cp -r openfoam-cases/ergun/CFD "$run"
    "$fg" info --case "$run"
    "$fg" voidage --case "$run" --dump openfoam-cases/ergun/reference/liggghts-settled.dump \
        --method divided
    foamDictionary -entry endTime -set 0.01 "$run/system/controlDict" >/dev/null
    foamDictionary -entry writeInterval -set 0.01 "$run/system/controlDict" >/dev/null
    cat >"$run/system/decomposeParDict" <<'DICT'
FoamFile { version 2.0; format ascii; class dictionary; object decomposeParDict; }
numberOfSubdomains 2;
method          simple;
coeffs          { n (1 1 2); }
DICT
    decomposePar -case "$run" -force >"$run/log.decomposePar"
    echo "grainPisoFoam -parallel on 2 ranks (log: $run/log.grainPisoFoam)"
    mpirun --oversubscribe -np 2 "$solver" -parallel -case "$run" >"$run/log.grainPisoFoam"
    reconstructPar -case "$run" -latestTime >"$run/log.reconstructPar"
    grep -q '^End' "$run/log.grainPisoFoam" || { echo "grainPisoFoam did not finish" >&2; exit 1; }
    [ -f "$run/0.01/p" ] && [ -f "$run/0.01/U" ] \
        || { echo "no fields at t = 0.01 in $run" >&2; exit 1; }
    grep 'time step continuity errors' "$run/log.grainPisoFoam" | tail -1
    "$fg" convert case --case "$run" --time latest --fields U,p,voidfraction -o "$run/ergun.vtu"
    echo "case: ok ($run, $run/ergun.vtu)"
}

steps=("$@")
[ "${#steps[@]}" -gt 0 ] || steps=(packages rust solver foamgrain case)
for s in "${steps[@]}"; do
    case "$s" in
        packages|rust|solver|foamgrain|case) "step_$s" ;;
        *) echo "unknown step \`$s\` (packages rust solver foamgrain case)" >&2; exit 2 ;;
    esac
done
