#!/bin/sh
# The race of issue 23 ("time to result"): OpenFOAM's own tracker (icoUncoupledKinematicParcelFoam
# v1912, serial) and pseudorigid (rigid spheres on 1 and 2 threads, then soft neo-Hookean ones
# of mu_s = 1 Pa on 1 thread) on the same spheres in the same field, the 90-degree bend
# (cases/bend), in one run: particle-steps, wall and CPU time, DE and the paired fates
# (examples/openfoam_race.rs; what is measured: src/studies/peer.rs).
#
# Usage: benches/peers/openfoam_race.sh [--ci] [OPTION...]
#   (default) the dataset: the bend's dataset mesh (cases/bend/Allrun's default, 47 000 cells,
#             in target/bend/case, made if missing), 1000 spheres at Stk 0.3, written to
#             paper-figures/peer-race/ (race.csv, race.md)
#   --ci      CI size (under a minute on 2 cores after the build): the 10 080-cell mesh of
#             cases/bend-ci.sh (cases/bend/ci, made if missing), 200 spheres, with --check
#             (fails on a broken script, lost spheres, or DEs beyond the argued bounds; never
#             on time), written to target/peer-race-ci/
#   OPTION    passed to the example: --integrator NAME (radau_iia, rosenbrock_w23, ...),
#             --tol T, --threads 1,2, --shear-modulus MU_S, --no-soft, --stk STK
# Environment: N (spheres), CASE_DIR (a solved bend case), RACE_OUT (output folder).
set -eu
repo=$(cd "$(dirname "$0")/../.." && pwd)
. "$repo/cases/install-openfoam.sh"
ci=
if [ "${1:-}" = "--ci" ]; then
    ci=1
    shift
fi
if [ -n "$ci" ]; then
    case_dir=${CASE_DIR:-$repo/cases/bend/ci}
    [ -f "$case_dir/bend.summary" ] || "$repo/cases/bend/Allrun" "$case_dir" 6 6 6
    n=${N:-200}
    out=${RACE_OUT:-$repo/target/peer-race-ci}
    set -- --check "$@"
else
    case_dir=${CASE_DIR:-$repo/target/bend/case}
    [ -f "$case_dir/bend.summary" ] || "$repo/cases/bend/Allrun" "$case_dir"
    n=${N:-1000}
    out=${RACE_OUT:-$repo/paper-figures/peer-race}
fi
cd "$repo"
RACE_OUT="$out" cargo run --release --quiet --example openfoam_race -- "$@" "$n" "$case_dir"
