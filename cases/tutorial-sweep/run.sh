#!/bin/sh
# OpenFOAM's own incompressible tutorials, meshed and solved here for the tutorial sweep
# (issue 57, docs/tutorial-sweep.md), then tracked by the `pseudorigid` command.
# Usage: cases/tutorial-sweep/run.sh NAME OUT_DIR [solve|track|all]
#   solve: copy the tutorial (Debian's v1912 examples) to OUT_DIR (replaced), mesh, solve,
#          write OUT_DIR/flux.txt (phi summed over each patch, outflow positive);
#   track: copy the scenes (scenes/NAME-*.toml) into OUT_DIR, validate and run each, then
#          check.py prints the table row and exits non-zero if a target is missed;
#   all (default): both.
# NAMES: cavity cavityRAS elbow pitzDaily pitzDailyExptInlet backwardFacingStep2D airFoil2D
#        planarContraction porousBlockage planarPoiseuille pipeCyclic wedgePipe squareBend
#        TJunction
# Changes to the tutorials (all said in docs/tutorial-sweep.md): pipeCyclic's codedFixedValue
# swirl inlet is written as fixedValue from the face centres, and it runs serially;
# planarPoiseuille runs the Newtonian (Stokes) model to t = 2; pisoFoam's cavity to t = 2;
# squareBend 300 SIMPLE iterations of 500.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
name=${1:?usage: run.sh NAME OUT_DIR [solve|track|all]}
out=${2:?usage: run.sh NAME OUT_DIR [solve|track|all]}
what=${3:-all}
export WM_PROJECT_DIR="${WM_PROJECT_DIR:-/usr/share/openfoam}"
tut=/usr/share/doc/openfoam-examples/examples/incompressible
bin="${CARGO_TARGET_DIR:-$repo/target}/release/pseudorigid"
# check.py reads frames.parquet with pyarrow: the CI venv has it (.ci/run), else python3's.
py=${PYTHON:-python3}
[ -x /tmp/pseudorigid-venv/bin/python ] && [ -z "${PYTHON:-}" ] && py=/tmp/pseudorigid-venv/bin/python
# Each OpenFOAM step is bounded (15 min in all on two cores is the sweep's budget).
run() { log="log.$1"; timeout 900 "$@" > "$log" 2>&1 || { echo "run.sh: $* failed (see $out/$log)" >&2; exit 1; }; }
latest() { ls -d [0-9]* | sort -g | tail -n 1; }
setend() { sed -i "s/^endTime .*/endTime         $2;/" "$1"; }

solve() {
    case "$name" in
        cavity)               src=$tut/icoFoam/cavity/cavity ;;
        cavityRAS)            src=$tut/pisoFoam/RAS/cavity ;;
        elbow)                src=$tut/icoFoam/elbow ;;
        pitzDaily)            src=$tut/simpleFoam/pitzDaily ;;
        pitzDailyExptInlet)   src=$tut/simpleFoam/pitzDailyExptInlet ;;
        backwardFacingStep2D) src=$tut/simpleFoam/backwardFacingStep2D ;;
        airFoil2D)            src=$tut/simpleFoam/airFoil2D ;;
        planarContraction)    src=$tut/pimpleFoam/laminar/planarContraction ;;
        porousBlockage)       src=$tut/pisoFoam/laminar/porousBlockage ;;
        planarPoiseuille)     src=$tut/pimpleFoam/laminar/planarPoiseuille ;;
        pipeCyclic)           src=$tut/simpleFoam/pipeCyclic ;;
        wedgePipe)            src=$here/wedgePipe ;;
        squareBend)           src=$tut/simpleFoam/squareBend ;;
        TJunction)            src=$tut/pimpleFoam/RAS/TJunction ;;
        *) echo "run.sh: unknown case $name" >&2; exit 2 ;;
    esac
    rm -rf "$out"
    mkdir -p "$out"
    cp -r "$src"/. "$out"/
    chmod -R u+w "$out"
    cd "$out"
    case "$name" in
        cavity)
            run blockMesh; run icoFoam ;;
        cavityRAS)
            setend system/controlDict 2; run blockMesh; run pisoFoam ;;
        elbow)
            gunzip -f elbow.msh.gz; run fluentMeshToFoam elbow.msh; run icoFoam ;;
        pitzDaily|pitzDailyExptInlet|backwardFacingStep2D|wedgePipe)
            run blockMesh; run simpleFoam ;;
        airFoil2D)
            run simpleFoam ;;
        squareBend)
            # 112 k cells: 300 SIMPLE iterations instead of 500 (the sweep's 15 min budget).
            setend system/controlDict 300; run blockMesh; run simpleFoam ;;
        TJunction)
            run blockMesh; run pimpleFoam ;;
        planarContraction)
            run blockMesh; run pimpleFoam ;;
        porousBlockage)
            run blockMesh; run topoSet; run pisoFoam ;;
        planarPoiseuille)
            sed "s|END_TIME|2|" system/controlDict.template > system/controlDict
            sed "s|LAMINAR_MODEL|Stokes|" constant/turbulenceProperties.template > constant/turbulenceProperties
            run blockMesh; run pimpleFoam ;;
        pipeCyclic)
            run blockMesh; run topoSet; run refineHexMesh c0 -overwrite
            rm -rf 0; cp -r 0.orig 0
            # codedFixedValue needs a compiler Debian's package cannot drive: the same swirl,
            # u = (1, 2 z, -2 y) = 2 Cf ^ e_x with u_x = 1, written as fixedValue from the
            # inlet's face centres.
            run postProcess -func writeCellCentres -time 0
            python3 "$here/swirl.py" 0
            run simpleFoam ;;
    esac
    python3 "$here/flux.py" . "$(latest)" > flux.txt
    cat flux.txt
}

track() {
    cd "$out"
    status=0
    for scene in "$here/scenes/$name"-*.toml; do
        kind=$(basename "$scene" .toml); kind=${kind#"$name"-}
        cp "$scene" "$out/$kind.toml"
        if ! "$bin" validate "$out/$kind.toml" > "log.validate.$kind" 2>&1; then
            echo "run.sh: $name $kind: validate refused: $(grep -v '^note' "log.validate.$kind" | head -n 3)"
            status=1
            continue
        fi
        rm -rf "$out/out-$kind"
        timeout 900 "$bin" run --quiet --csv "$out/$kind.toml" --out "$out/out-$kind" > "log.run.$kind" 2>&1 \
            || { echo "run.sh: $name $kind: run failed (see $out/log.run.$kind)"; status=1; continue; }
        "$py" "$here/check.py" "$out" "$kind" "$bin" || status=1
    done
    return $status
}

case "$what" in
    solve) solve ;;
    track) track ;;
    all) (solve); track ;;
    *) echo "run.sh: solve, track or all" >&2; exit 2 ;;
esac
