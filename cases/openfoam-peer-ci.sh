#!/bin/sh
# CI check of OpenFOAM's own tracker as a peer (a minute on 2 cores after the build): the same
# 400 rigid spheres at Stk 0.4 through the coarse airway (0.75 mm cells, made by
# cases/bifurcation-ci.sh at cases/bifurcation/ci; made here if missing) tracked by
# icoUncoupledKinematicParcelFoam (benches/peers/openfoam_tracker/run.sh) and by pseudorigid,
# compared particle by particle (`examples/openfoam_peer.rs --check`): fails if the script
# breaks, a particle is lost, fails or is left suspended, the DEs differ by more than 5 combined
# standard errors + 0.05, or more than 18 % of the fates differ (the bounds are argued in the
# example). The table goes to target/openfoam-peer-ci, not to paper-figures.
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
. "$repo/cases/install-openfoam.sh"
work="$repo/cases/bifurcation/ci"
if [ ! -f "$work/log.summary" ]; then
    python3 -c "import numpy, skimage" 2>/dev/null || python3 -m pip install --quiet -r "$repo/cases/bifurcation/requirements.txt" \
        || python3 -m pip install --quiet --break-system-packages -r "$repo/cases/bifurcation/requirements.txt"
    "$repo/cases/bifurcation/Allrun" 0.75e-3 "$work"
fi
cd "$repo"
OPENFOAM_PEER_OUT="$repo/target/openfoam-peer-ci" cargo run --release --quiet --example openfoam_peer -- --check "$work" 400 0.4
echo "openfoam-peer-ci: OK"
