#!/bin/sh
# Lid-driven cavity: mesh -> steady laminar solve -> U in the form reference-data ships it.
# Usage: cases/cavity-allrun.sh CASE_DIR (each case's Allrun calls this with its own directory).
# Run heavy cases as `nice -n 15 ./Allrun`, serial (one core).
# Result: the solved case (constant/polyMesh and the last time directory, which
# `flow::openfoam::FoamCase` reads), CASE_DIR/export/U.gz (the last U as ASCII with 6
# significant digits, gzipped by foamFormatConvert: the file of reference-data/cavity-*-foam),
# log.* files and log.summary (iterations, final residuals, run time).
set -eu
cd "${1:?usage: cavity-allrun.sh CASE_DIR}"
export WM_PROJECT_DIR="${WM_PROJECT_DIR:-/usr/share/openfoam}"
for tool in blockMesh simpleFoam foamFormatConvert; do
    command -v "$tool" >/dev/null || { echo "Allrun: $tool not found (apt-get install openfoam)" >&2; exit 1; }
done

rm -rf constant/polyMesh export log.* processor* postProcessing
find . -maxdepth 1 -type d -regex './[0-9.e+-]+' ! -name 0 -exec rm -rf {} +

start=$(date +%s)
blockMesh > log.blockMesh 2>&1
simpleFoam > log.simpleFoam 2>&1
solved=$(date +%s)
if ! grep -q "SIMPLE solution converged" log.simpleFoam; then
    echo "Allrun: simpleFoam stopped without meeting residualControl (see log.simpleFoam)" >&2
    exit 1
fi
# Rewrite the last time (and the mesh) as compressed ASCII with 6 digits; the case's own
# controlDict (binary, 10 digits) is restored afterwards.
cp system/controlDict system/controlDict.solve
trap 'mv system/controlDict.solve system/controlDict' EXIT
sed -i 's/^writeFormat .*/writeFormat     ascii;/; s/^writePrecision .*/writePrecision  6;/; s/^writeCompression .*/writeCompression on;/' system/controlDict
foamFormatConvert -latestTime > log.foamFormatConvert 2>&1

iters=$(ls -d [1-9]* | sort -n | tail -n 1)
mkdir -p export
cp "$iters/U.gz" export/U.gz
end=$(date +%s)
{
    echo "case=$(basename "$PWD")"
    echo "simple_iterations=$iters"
    echo "final_initial_residuals=$(grep -E 'Solving for' log.simpleFoam | tail -n 4 | sed -E 's/.*Solving for ([A-Za-z]+), Initial residual = ([^,]+),.*/\1=\2/' | tr '\n' ' ')"
    echo "solve_seconds=$((solved - start))"
    echo "total_seconds=$((end - start))"
} > log.summary
cat log.summary
