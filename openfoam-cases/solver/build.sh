#!/usr/bin/env bash
# Builds grainPisoFoam (the VANS PISO solver of foamgrain) against Debian's OpenFOAM v1912.
#
# Debian ships OpenFOAM's binaries and libraries (packages openfoam, libopenfoam) but no headers
# and no wmake. This script, on Debian bookworm:
#   1. installs the packages it needs (only the missing ones; needs root then),
#   2. downloads Debian's `openfoam` source package (apt-get source --download-only, a deb-src
#      entry is added if there is none) and extracts the headers of the four libraries the solver
#      uses (OpenFOAM, OSspecific/POSIX, finiteVolume, meshTools) into the cache,
#   3. makes their lnInclude folders (a symlink to every source file of a library),
#   4. compiles grainPisoFoam with plain g++ command lines (the flags Debian's build used:
#      double precision, 32-bit labels) and links it with Debian's libraries and Open MPI (the
#      flags of `mpicxx --showme:compile` / `--showme:link`; the `mpi` coupling source talks
#      to foamgrain's coupler over MPI),
#   5. installs the binary as $FOAMGRAIN_CACHE/bin/grainPisoFoam.
# Every step is skipped when its result is already there, so a second run takes about a second.
# The last line printed is `grainPisoFoam=<path of the binary>`.
#
# Environment: FOAMGRAIN_CACHE (default ~/.cache/foamgrain), CXX (default g++).
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
cache="${FOAMGRAIN_CACHE:-$HOME/.cache/foamgrain}"
version="1912.200626"
src_root="$cache/openfoam-$version"
bin_dir="$cache/bin"
cxx="${CXX:-g++}"
packages=(openfoam libopenfoam openmpi-bin libopenmpi-dev g++ dpkg-dev bzip2)
# Source trees extracted from the openfoam source package, and those of them that get an
# lnInclude (wmake's flat header directory).
src_trees=(OpenFOAM OSspecific/POSIX finiteVolume meshTools TurbulenceModels transportModels)
libs_with_headers=(OpenFOAM OSspecific/POSIX finiteVolume meshTools
                   TurbulenceModels/turbulenceModels TurbulenceModels/incompressible)

say() { printf 'build.sh: %s\n' "$*" >&2; }

mkdir -p "$cache" "$bin_dir"
# One build at a time (tests and users may start this script concurrently).
exec 9>"$cache/.build.lock"
flock 9

# --- 1. packages --------------------------------------------------------------------------
missing=()
for p in "${packages[@]}"; do
    if [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" != "install ok installed" ]; then
        missing+=("$p")
    fi
done
if [ "${#missing[@]}" -gt 0 ]; then
    if [ "$(id -u)" -ne 0 ]; then
        say "missing packages: ${missing[*]} (run as root, or: sudo apt-get install ${missing[*]})"
        exit 1
    fi
    say "installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
    say "packages present: ${packages[*]}"
fi
installed="$(dpkg-query -W -f='${Version}' libopenfoam)"
case "$installed" in
    "$version"-*) ;;
    *) say "libopenfoam $installed is installed; this script expects $version (bookworm)"; exit 1 ;;
esac

# --- 2. headers from Debian's source package ----------------------------------------------
# A cache made before the turbulence models were used lacks some trees: extract those.
missing_trees=()
for tree in "${src_trees[@]}"; do
    [ -f "$src_root/.extracted" ] && [ -d "$src_root/src/$tree" ] || missing_trees+=("$tree")
done
if [ "${#missing_trees[@]}" -gt 0 ]; then
    has_deb_src() {
        grep -rqsE '^(deb-src[[:space:]]|Types:.*deb-src)' /etc/apt/sources.list /etc/apt/sources.list.d/
    }
    if ! has_deb_src; then
        if [ "$(id -u)" -ne 0 ]; then
            say "no deb-src entry in /etc/apt (run as root to add one)"
            exit 1
        fi
        say "adding /etc/apt/sources.list.d/foamgrain-src.sources (deb-src bookworm main)"
        cat >/etc/apt/sources.list.d/foamgrain-src.sources <<'SOURCES'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
        apt-get update -qq
    fi
    download="$cache/download"
    rm -rf "$download" "$src_root.partial"
    mkdir -p "$download" "$src_root.partial"
    say "downloading the openfoam source package into $download"
    (cd "$download" && apt-get source --download-only -qq "openfoam=$version-1") >&2
    tarball="$(ls "$download"/openfoam_"$version".orig.tar.*)"
    top="openfoam-OpenFOAM-v$version"
    patterns=()
    for tree in "${src_trees[@]}"; do patterns+=("$top/src/$tree/*"); done
    say "extracting src/{$(IFS=,; echo "${src_trees[*]}")} from $(basename "$tarball")"
    tar -xf "$tarball" -C "$src_root.partial" --strip-components=1 --wildcards "${patterns[@]}"
    touch "$src_root.partial/.extracted"
    rm -rf "$src_root"
    mv "$src_root.partial" "$src_root"
    rm -rf "$download"
else
    say "headers present in $src_root"
fi

# --- 3. lnInclude folders -------------------------------------------------------------------
for lib in "${libs_with_headers[@]}"; do
    dir="$src_root/src/$lib"
    if [ ! -f "$dir/lnInclude/.complete" ]; then
        say "making $dir/lnInclude"
        rm -rf "$dir/lnInclude"
        mkdir -p "$dir/lnInclude"
        find "$dir" -path "$dir/lnInclude" -prune -o -type f \
            \( -name '*.H' -o -name '*.C' -o -name '*.h' -o -name '*.hxx' -o -name '*.cxx' \) \
            -print0 | xargs -0 ln -sf -t "$dir/lnInclude"
        touch "$dir/lnInclude/.complete"
    fi
done

# --- 4. compile ---------------------------------------------------------------------------
solver_dir="$here/grainPisoFoam"
cxxflags=(-std=c++14 -pthread -m64 -DOPENFOAM=1912 -DWM_DP -DWM_LABEL_SIZE=32 -DNoRepository
          -ftemplate-depth-100 -fPIC -O3 -Wall -Wno-unused-parameter -Wno-attributes)
includes=(-I"$solver_dir")
for lib in "${libs_with_headers[@]}"; do includes+=(-I"$src_root/src/$lib/lnInclude"); done
# pisoFoam's include directories for the transport model (Make/options of v1912).
includes+=(-I"$src_root/src/transportModels"
           -I"$src_root/src/transportModels/incompressible/singlePhaseTransportModel")
# Open MPI (the same library Debian's libPstream uses); word splitting of mpicxx's flags intended.
read -r -a mpi_compile <<<"$(mpicxx --showme:compile)"
read -r -a mpi_link <<<"$(mpicxx --showme:link)"
includes+=("${mpi_compile[@]}")
ldlibs=(-L/usr/lib -lturbulenceModels -lincompressibleTurbulenceModels
        -lincompressibleTransportModels -lfiniteVolume -lmeshTools -lOpenFOAM -lPstream
        "${mpi_link[@]}" -ldl -lm)
target="$bin_dir/grainPisoFoam"
stamp="$target.sources.sha256"
digest="$( { cat "$solver_dir"/*.C "$solver_dir"/*.H; echo "${cxxflags[*]} ${includes[*]} ${ldlibs[*]}";
             "$cxx" --version | head -1; echo "$installed"; } | sha256sum | cut -d' ' -f1)"
if [ -x "$target" ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$digest" ]; then
    say "grainPisoFoam is up to date"
else
    say "compiling grainPisoFoam ($cxx ${cxxflags[*]})"
    obj="$cache/grainPisoFoam.o"
    "$cxx" "${cxxflags[@]}" "${includes[@]}" -c "$solver_dir/grainPisoFoam.C" -o "$obj"
    say "linking grainPisoFoam (${ldlibs[*]})"
    "$cxx" -pthread -m64 -Xlinker --add-needed -Xlinker --no-as-needed "$obj" \
        "${ldlibs[@]}" -o "$target.partial"
    mv "$target.partial" "$target"
    echo "$digest" >"$stamp"
    rm -f "$obj"
fi
echo "grainPisoFoam=$target"
