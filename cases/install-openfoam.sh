#!/bin/sh
# Install OpenFOAM v1912 from Debian's packages if it is missing (CI machines start clean), and
# point WM_PROJECT_DIR at it. Sourced by the end-to-end case scripts.
if ! command -v simpleFoam >/dev/null 2>&1; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq openfoam >/dev/null
fi
export WM_PROJECT_DIR="${WM_PROJECT_DIR:-/usr/share/openfoam}"
