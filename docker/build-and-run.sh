#!/usr/bin/env bash
# foamgrain on Debian bookworm, step by step: the steps docker/Dockerfile runs, one RUN per
# step, so the image and a plain machine (as root) build and run the same way.
#
#   docker/build-and-run.sh              all steps in order
#   docker/build-and-run.sh STEP...      only these steps
#
# Steps:
#   packages   apt packages: OpenFOAM v1912 (openfoam, libopenfoam, and openfoam-examples, whose
#              cases `foamgrain fluid` is compared on), LIGGGHTS 3.8.0 (liggghts,
#              libliggghts-dev), OpenMPI, libclang (for the mpi crate's bindings), g++, dpkg-dev,
#              bzip2, curl and ca-certificates (for rustup), git, python3
#   rust       Rust stable through rustup, unless cargo is already on PATH
#   solver     grainPisoFoam with openfoam-cases/solver/build.sh (headers from Debian's
#              openfoam source package; idempotent)
#   foamgrain  cargo build --release -p cli --features mpi,liggghts (the foamgrain binary with
#              the grainPisoFoam and LIGGGHTS backends)
#   case       the Ergun reference case as a real co-simulation: `foamgrain run` with
#              grainPisoFoam on 2 MPI ranks and LIGGGHTS in-process (LIGGGHTS packs the bed
#              first), its checks (Ergun pressure drop, fluidised plateau), and `foamgrain
#              convert case` of the last time to VTK
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
    local pkgs=(openfoam libopenfoam openfoam-examples liggghts libliggghts-dev openmpi-bin libopenmpi-dev
                libclang-dev g++ dpkg-dev bzip2 curl ca-certificates git python3)
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
    step "foamgrain: cargo build --release -p cli --features mpi,liggghts"
    cargo build --release -p cli --features mpi,liggghts
    echo "foamgrain=$(target_dir)/release/foamgrain"
}

step_case() {
    step "case: openfoam-cases/ergun, grainPisoFoam on 2 ranks + LIGGGHTS in-process"
    local fg run
    fg="$(target_dir)/release/foamgrain"
    [ -x "$fg" ] || { echo "no $fg: run the foamgrain step" >&2; exit 1; }
    bash openfoam-cases/solver/build.sh >/dev/null
    export OMPI_MCA_rmaps_base_oversubscribe=1
    run="${FOAMGRAIN_RUN_DIR:-${TMPDIR:-/tmp}/foamgrain-ergun}"
    rm -rf "$run"
    cp -r openfoam-cases/ergun "$run"
    "$fg" run "$run" --fluid openfoam --dem liggghts --np 2
    "$fg" convert case --case "$run/CFD" --time latest --fields U,p,voidfraction \
        -o "$run/ergun.vtu"
    echo "case: ok ($run: postProcessing/validation.json, ergun.vtu)"
}

steps=("$@")
[ "${#steps[@]}" -gt 0 ] || steps=(packages rust solver foamgrain case)
for s in "${steps[@]}"; do
    case "$s" in
        packages|rust|solver|foamgrain|case) "step_$s" ;;
        *) echo "unknown step \`$s\` (packages rust solver foamgrain case)" >&2; exit 2 ;;
    esac
done
