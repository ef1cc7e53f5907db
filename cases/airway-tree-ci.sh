#!/bin/sh
# End-to-end CI check of the airway tree (a few minutes on 2 cores): install OpenFOAM v1912 and
# the geometry script's Python packages if missing, generate the rotated tree's wall surface,
# mesh it coarsely (0.5 mm cells, about 23 000 cells), solve it with simpleFoam (Re = 500 in
# G3), check that the eight outlets carry the inlet flow to 1 %, read the fresh case with the
# crate's OpenFOAM reader and track 40 rigid spheres at Stk = 0.4 through it
# (`examples/bifurcation_tracer`: fails if a particle fails or none escapes).
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)

. "$repo/cases/install-openfoam.sh"
python3 -c "import numpy, skimage" 2>/dev/null || python3 -m pip install --quiet -r "$repo/cases/airway-tree/requirements.txt" \
    || python3 -m pip install --quiet --break-system-packages -r "$repo/cases/airway-tree/requirements.txt"

work="$repo/cases/airway-tree/ci"
"$repo/cases/airway-tree/Allrun" rotated 0.5e-3 "$work"
awk -F= '/^flow_rate_inlet=/ { qin = -$2 } /^flow_rate_outlet/ { q += $2 }
    END { r = (q - qin) / qin; printf "outlets/inlet - 1 = %.2e\n", r; exit (r > 0.01 || r < -0.01) }' "$work/log.summary"
cd "$repo"
cargo run --release --quiet --example bifurcation_tracer -- "$work" 40 0.4
echo "airway-tree-ci: OK"
