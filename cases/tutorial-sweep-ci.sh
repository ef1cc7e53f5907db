#!/bin/sh
# OpenFOAM's own tutorials as a new user brings them (issue 57, docs/tutorial-sweep.md): the
# smallest of the sweep, each copied from Debian's openfoam-examples, meshed, solved and tracked
# by the `pseudorigid` command with the scenes of cases/tutorial-sweep/scenes (1 000 tracers and
# 1 000 inertial spheres each). check.py fails the run on any failed particle, any particle
# probed outside the mesh, any tracer deposited on a wall, and any tracer outlet share more
# than 3 binomial standard errors from the face fluxes (phi).
#   cavity: icoFoam's lid-driven cavity (400 cells, a moving wall, 2-D, closed);
#   elbow:  icoFoam's elbow (918 cells, fluentMeshToFoam, 2-D, two inlets);
#   planarPoiseuille: pimpleFoam's periodic channel (40 cells, cyclic and symmetryPlane, closed).
# Not here for its run time: wedgePipe (2 000 cells, wedge; 8 min on the shared machine).
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
. "$repo/cases/install-openfoam.sh"
[ -d /usr/share/doc/openfoam-examples/examples ] \
    || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq openfoam-examples >/dev/null
cd "$repo"
cargo build --release --bin pseudorigid
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for name in cavity elbow planarPoiseuille; do
    cases/tutorial-sweep/run.sh "$name" "$work/$name"
done
cat "$work/table.tsv"
echo "tutorial-sweep-ci: OK"
