#!/bin/sh
# Run an example scene with the `pseudorigid` command and read its ParaView files back with
# VTK (Debian: python3-vtk9, python3-numpy; xvfb for the headless render), comparing every
# array with the run's CSV files; render one frame to a PNG.
#
#   cases/vtk-check.sh [PNG]     (default PNG: a temporary file)
#
# Needs: cargo; /usr/bin/python3 with vtk and numpy (apt-get install python3-vtk9
# python3-numpy xvfb). VTK's render window needs an X server: without DISPLAY the check runs
# under xvfb-run.
set -eu
root="$(cd "$(dirname "$0")/.." && pwd)"
png="${1:-}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
cd "$root"
cargo build --release --bin pseudorigid
target="${CARGO_TARGET_DIR:-$root/target}"
"$target/release/pseudorigid" run --quiet --csv scenes/shear_injection.toml --out "$out/run"
set -- /usr/bin/python3 "$root/cases/vtk-check.py" "$out/run"
if [ -n "$png" ]; then
    set -- "$@" --png "$png" --frame 15
fi
if [ -z "${DISPLAY:-}" ]; then
    set -- xvfb-run -a "$@"
fi
"$@"
