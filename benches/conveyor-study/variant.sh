#!/usr/bin/env bash
# The full conveyor's sensitivity study (issue 30 item 2): makes one variant of
# openfoam-cases/pneumatic-conveying-full in DIR ready for `foamgrain run DIR`.
#
#   benches/conveyor-study/variant.sh DIR SCALE [dp=D] [rhop=R] [pout=P] [end=T] [dt=S]
#
# SCALE  the mesh (geometry.py --full --scale SCALE: 1 → 21 104 cells, 1.25 → 45 828)
# dp     particle diameter, m (default the case's 5e-4); the bed's volume is kept: the
#        particles per packing block are 500 (5e-4/dp)³, rounded
# rhop   particle density, kg/m³ (default 1500)
# pout   the vented outlet's kinematic pressure, m²/s² (default the case's −2200)
# end    endTime, s (default 0.2)
# dt     the fluid step (default 1e-4 s, the seed's coarse step; the DEM step stays 5e-6 s,
#        so a coupling step is dt / 5e-6 DEM steps)
#
# Then: foamgrain run DIR --np 1
# The seed gives neither the particles' size and density nor the vacuum level: the study
# varies one at a time from the case as committed and reports the downstream tube's particle
# velocity (`integrals.csv`, benches/conveyor-study/table.py), never tuned into a pass.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$here/../.."
dir="${1:?usage: variant.sh DIR SCALE [dp=D] [rhop=R] [pout=P] [end=T] [dt=S]}"
scale="${2:?usage: variant.sh DIR SCALE …}"
shift 2
dp=0.0005 rhop=1500 pout=-2200 end=0.2 dt=1e-4
for kv in "$@"; do
    case "$kv" in
        dp=*|rhop=*|pout=*|end=*|dt=*) declare "${kv%%=*}=${kv#*=}" ;;
        *) echo "variant.sh: unknown setting '$kv' (dp, rhop, pout, end, dt)" >&2; exit 1 ;;
    esac
done
[ ! -e "$dir" ] || { echo "variant.sh: $dir exists" >&2; exit 1; }
export WM_PROJECT_DIR=/usr/share/openfoam
"$repo/.ci/copy-case" "$repo/openfoam-cases/pneumatic-conveying-full" "$dir"
python3 "$repo/openfoam-cases/pneumatic-conveying/geometry.py" --full --scale "$scale" \
    --out "$dir/CFD/system" > "$dir/geometry.log"
blockMesh -case "$dir/CFD" > "$dir/blockMesh.log" 2>&1 \
    || { echo "variant.sh: blockMesh failed, see $dir/blockMesh.log" >&2; exit 1; }
every=$(python3 -c "n = $dt / 5e-6; r = round(n); assert abs(n - r) < 1e-9 and r >= 1, 'dt must be a multiple of 5e-6'; print(r)")
np=$(python3 -c "print(round(500 * (5e-4 / $dp) ** 3))")
sed -i "s/^deltaT .*/deltaT          $dt;/; s/^endTime .*/endTime         $end;/" \
    "$dir/CFD/system/controlDict"
sed -i "s/^couplingInterval .*/couplingInterval    $every;/" "$dir/CFD/constant/couplingProperties"
sed -i "s/couple_every 4 /couple_every $every /" "$dir/DEM/in.liggghts_run"
sed -i "s/outlet  { type fixedValue; value uniform -2200; }/outlet  { type fixedValue; value uniform $pout; }/" \
    "$dir/CFD/0/p"
grep -q "value uniform $pout;" "$dir/CFD/0/p" || { echo "variant.sh: outlet pressure not set" >&2; exit 1; }
# the deck's index variables (`foamgrain run --var` sets the packing deck's only)
sed -i -e "s/^variable        np index 500 /variable        np index $np /" \
    -e "s/^variable        dp index 0.0005 /variable        dp index $dp /" \
    -e "s/^variable        rhop index 1500 /variable        rhop index $rhop /" "$dir/DEM/in.liggghts_run"
grep -q "^variable        np index $np " "$dir/DEM/in.liggghts_run" \
    && grep -q "^variable        dp index $dp " "$dir/DEM/in.liggghts_run" \
    && grep -q "^variable        rhop index $rhop " "$dir/DEM/in.liggghts_run" \
    || { echo "variant.sh: deck variables not set" >&2; exit 1; }
echo "$dir: scale $scale, dp $dp m, rhop $rhop kg/m³, $np particles per block, outlet $pout m²/s², dt $dt s ($every DEM steps), end $end s"
