#!/bin/sh
# Lid-driven cavity: mesh -> steady laminar solve -> grad(U) -> legacy VTK export.
# Usage: cases/cavity-allrun.sh CASE_DIR (each case's Allrun calls this with its own directory).
# Run heavy cases as `nice -n 15 ./Allrun`, serial (one core).
# Result: CASE_DIR/export/cavity.vtk (cell + point data of U and grad(U)), log.* files and
# log.summary (iterations, final residuals, run time).
set -eu
cd "${1:?usage: cavity-allrun.sh CASE_DIR}"
export WM_PROJECT_DIR="${WM_PROJECT_DIR:-/usr/share/openfoam}"
for tool in blockMesh simpleFoam postProcess foamToVTK; do
    command -v "$tool" >/dev/null || { echo "Allrun: $tool not found (apt-get install openfoam)" >&2; exit 1; }
done

rm -rf constant/polyMesh VTK export log.* processor* postProcessing
find . -maxdepth 1 -type d -regex './[0-9.e+-]+' ! -name 0 -exec rm -rf {} +

start=$(date +%s)
blockMesh > log.blockMesh 2>&1
simpleFoam > log.simpleFoam 2>&1
solved=$(date +%s)
if ! grep -q "SIMPLE solution converged" log.simpleFoam; then
    echo "Allrun: simpleFoam stopped without meeting residualControl (see log.simpleFoam)" >&2
    exit 1
fi
postProcess -func 'grad(U)' -latestTime > log.postProcess 2>&1
foamToVTK -legacy -latestTime -no-boundary -fields '(U grad(U))' > log.foamToVTK 2>&1

mkdir -p export
vtk=$(ls -t VTK/*.vtk | head -n 1)
cp "$vtk" export/cavity.vtk
end=$(date +%s)
iters=$(ls -d [1-9]* | sort -n | tail -n 1)
{
    echo "case=$(basename "$PWD")"
    echo "simple_iterations=$iters"
    echo "final_initial_residuals=$(grep -E 'Solving for' log.simpleFoam | tail -n 4 | sed -E 's/.*Solving for ([A-Za-z]+), Initial residual = ([^,]+),.*/\1=\2/' | tr '\n' ' ')"
    echo "solve_seconds=$((solved - start))"
    echo "total_seconds=$((end - start))"
} > log.summary
cat log.summary
