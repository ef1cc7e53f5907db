#!/bin/sh
# End-to-end CI check of the airway bifurcation (a minute on 2 cores): install OpenFOAM v1912
# and the geometry script's Python packages if missing, generate the wall surface, mesh it
# coarsely (0.75 mm cells, about 7 000 cells), solve it with simpleFoam (Re = 500), read the
# fresh case with the crate's OpenFOAM reader and track 40 rigid spheres at Stk = 0.4 through it
# (`examples/bifurcation_tracer`: fails if a particle fails or none escapes).
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)

. "$repo/cases/install-openfoam.sh"
python3 -c "import numpy, skimage" 2>/dev/null || python3 -m pip install --quiet -r "$repo/cases/bifurcation/requirements.txt" \
    || python3 -m pip install --quiet --break-system-packages -r "$repo/cases/bifurcation/requirements.txt"

work="$repo/cases/bifurcation/ci"
"$repo/cases/bifurcation/Allrun" 0.75e-3 "$work"
cd "$repo"
cargo run --release --quiet --example bifurcation_tracer -- "$work" 40 0.4
echo "bifurcation-ci: OK"
