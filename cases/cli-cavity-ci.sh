#!/bin/sh
# The `pseudorigid` command on a real OpenFOAM case: solve the 12^3 CI cavity
# (cases/cavity-ci, seconds), run scenes/cavity.toml on it for 2 s, and check the run's
# files with VTK when python3-vtk9 is installed. Installs OpenFOAM v1912 from apt if missing.
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
. "$repo/cases/install-openfoam.sh"
"$repo/cases/cavity-ci/Allrun"
cd "$repo"
cargo build --release --bin pseudorigid
target="${CARGO_TARGET_DIR:-$repo/target}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e 's|^case = .*|case = "'"$repo"'/cases/cavity-ci"|' -e 's|^t_end = .*|t_end = 2.0|' scenes/cavity.toml > "$work/cavity.toml"
"$target/release/pseudorigid" validate "$work/cavity.toml"
"$target/release/pseudorigid" run --quiet --csv "$work/cavity.toml" --out "$work/out"
if grep -q '^0,failed,' "$work/out/results.csv"; then
    cat "$work/out/results.csv" >&2
    echo "cli-cavity-ci: the particle's run failed" >&2
    exit 1
fi
if /usr/bin/python3 -c 'import vtk' 2>/dev/null; then
    /usr/bin/python3 cases/vtk-check.py "$work/out"
fi
echo "cli-cavity-ci: OK"
