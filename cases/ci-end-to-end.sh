#!/bin/sh
# End-to-end CI check of the OpenFOAM pipeline (run as root on a clean Debian machine, a few
# minutes): install OpenFOAM v1912 from apt if missing, run the 12^3 cavity case (mesh, steady
# solve), read the solved case with the crate's OpenFOAM reader and track a passive tracer
# through it.
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)

. "$repo/cases/install-openfoam.sh"

"$repo/cases/cavity-ci/Allrun"

cd "$repo"
# Lid speed 0.0813 m/s (cases/cavity-ci/system/caseParameters), 2 s of tracking.
cargo run --quiet --example cavity_tracer -- cases/cavity-ci 0.0813 2.0
