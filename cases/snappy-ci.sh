#!/bin/sh
# End-to-end CI check of the polyhedral OpenFOAM path (a minute on 2 cores): install OpenFOAM
# v1912 from apt if missing, mesh the sphere-in-a-channel case with snappyHexMesh (NX = 10),
# solve it with simpleFoam (laminar, Re = 20 on the sphere), probe the result with
# `examples/probe_flow` and check the probe: the inflow near the inlet, no-slip on the sphere,
# and points inside the sphere or beyond the outlet reported outside.
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)

. "$repo/cases/install-openfoam.sh"

work="$repo/cases/snappy-test/ci"
"$repo/cases/snappy-test/Allmesh" 10 "$work"
(cd "$work" && simpleFoam > log.simpleFoam 2>&1)
grep -q "SIMPLE solution converged" "$work/log.simpleFoam" || {
    echo "snappy-ci: simpleFoam did not converge (see $work/log.simpleFoam)" >&2
    exit 1
}

# Near the inlet (u1 = 1 within 10 %); at the sphere's front stagnation point (radius 0.1
# around (0.5, 0.2, 0.2); no-slip, but on this coarse mesh the snapped wall and the O(h)
# reconstruction leave |u1| up to about 0.1, so |u1| < 0.2 = 20 % of the inflow); inside the
# sphere; beyond the outlet.
cat > "$work/points.csv" <<'POINTS'
x,y,z
0.02,0.2,0.2
0.4,0.2,0.2
0.5,0.2,0.2
1.5,0.2,0.2
POINTS
cd "$repo"
cargo run --release --quiet --example probe_flow -- "$work" latest "$work/points.csv" "$work/probe.csv"
awk -F, '
    NR == 2 && !($4 == 1 && $5 > 0.9 && $5 < 1.1) { print "inlet: " $0; bad = 1 }
    NR == 3 && !($4 == 1 && $5 < 0.2 && $5 > -0.2) { print "sphere surface: " $0; bad = 1 }
    NR == 4 && $4 != 0 { print "inside the sphere: " $0; bad = 1 }
    NR == 5 && $4 != 0 { print "beyond the outlet: " $0; bad = 1 }
    END { exit bad }
' "$work/probe.csv" || { echo "snappy-ci: unexpected probe values (above)" >&2; exit 1; }
echo "snappy-ci: OK"
