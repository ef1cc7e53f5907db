#!/bin/sh
# OpenFOAM's own particle tracker (icoUncoupledKinematicParcelFoam, v1912) on a frozen steady
# field: the peer of pseudorigid's tracking. See README.md here.
#
# Usage: run.sh CASE_DIR PARTICLES.csv OUT_DIR
#   CASE_DIR       a solved OpenFOAM case: constant/polyMesh (plain or gzipped),
#                  constant/transportProperties (nu; or NU below) and the steady U (and phi) in
#                  its last time directory
#   PARTICLES.csv  index,x,y,z,u,v,w,d,rho (SI): position, initial velocity, diameter, density
#   OUT_DIR        created; OUT_DIR/case is the kinematic-cloud case, OUT_DIR/fates.csv the result
# Environment (optional):
#   END_TIME   tracking time in s (default: 10 mean residence times V/Q of CASE_DIR, V from
#              checkMesh, Q the inlet flow rate from phi)
#   FLUID_RHO  fluid density in kg/m^3 (default 1.208, the bifurcation's air; a kinematic case
#              has none)
#   GRAVITY    gravity vector "(gx gy gz)" in m/s^2 (default "(9.81 0 0)", the bifurcation's
#              +e1, src/studies/bifurcation/setup.rs GRAVITY)
#   DELTA_T    outer time step in s (default 1e-4; parcels sub-step within it at maxCo 0.3)
#   INLET      name of the inlet patch for the flow rate (default inlet)
#   NU         kinematic viscosity in m^2/s (default: nu of CASE_DIR/constant/transportProperties;
#              needed for the shipped fields of reference-data, which keep only the mesh and U)
#   Variants for measuring what the peer's choices do (defaults are the peer):
#   STOKES_SCALE (1000: rho_f/1000 and 1000 nu, sphereDrag in its Stokes limit; 1: the real
#   fluid, sphereDrag with its finite-Re correction), MAX_CO (0.3: parcel sub-steps of at most
#   0.3 of a cell), U_INTERPOLATION (cellPoint; cell: the cell value), U_INTEGRATION
#   (analytical: exact over a sub-step for the frozen interpolated velocity; Euler: implicit Euler)
# Output: OUT_DIR/fates.csv (index,fate,patch,t,x,y,z; fate deposited | escaped | suspended |
# not_injected), OUT_DIR/summary.txt (key=value: wall times of both phases and of the tracking
# phase alone, its CPU time (ExecutionTime) and that CPU time split into loading the case
# (load_cpu_seconds, up to the time loop) and tracking (track_cpu_seconds), the injection
# phase's CPU time (inject_cpu_seconds), outer steps, parcel outer steps, counts), logs in
# OUT_DIR/case.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
case_dir=$(cd "${1:?usage: run.sh CASE_DIR PARTICLES.csv OUT_DIR}" && pwd)
particles=${2:?usage: run.sh CASE_DIR PARTICLES.csv OUT_DIR}
out=${3:?usage: run.sh CASE_DIR PARTICLES.csv OUT_DIR}
export WM_PROJECT_DIR="${WM_PROJECT_DIR:-/usr/share/openfoam}"
command -v icoUncoupledKinematicParcelFoam >/dev/null || {
    echo "run.sh: icoUncoupledKinematicParcelFoam not found (apt-get install openfoam)" >&2; exit 1; }
fluid_rho=${FLUID_RHO:-1.208}
gravity=${GRAVITY:-(9.81 0 0)}
dt=${DELTA_T:-1e-4}
inlet=${INLET:-inlet}

mkdir -p "$out"
particles=$(cd "$(dirname "$particles")" && pwd)/$(basename "$particles")
out=$(cd "$out" && pwd)
work="$out/case"
rm -rf "$work"
mkdir -p "$work/0" "$work/constant" "$work/system"
last=$(cd "$case_dir" && ls -d [0-9]* | sort -g | tail -n 1)
[ -f "$case_dir/$last/U" ] || [ -f "$case_dir/$last/U.gz" ] || { echo "run.sh: no U in $case_dir/$last" >&2; exit 1; }
cp -r "$case_dir/constant/polyMesh" "$work/constant/"
for f in U U.gz phi phi.gz; do [ -f "$case_dir/$last/$f" ] && cp "$case_dir/$last/$f" "$work/0/"; done
if [ -n "${NU:-}" ]; then
    nu=$NU
elif [ -f "$case_dir/constant/transportProperties" ]; then
    nu=$(sed -n 's/^ *nu *\([^;]*\);.*/\1/p' "$case_dir/constant/transportProperties" | awk '{print $NF}')
fi
[ -n "${nu:-}" ] || { echo "run.sh: no nu in $case_dir/constant/transportProperties and no NU given" >&2; exit 1; }

python3 "$here/peer.py" setup "$work" "$particles" --nu "$nu" --fluid-rho "$fluid_rho" --gravity "$gravity"
cd "$work"

# The tracking time: 10 V/Q unless given.
if [ -z "${END_TIME:-}" ]; then
    python3 "$here/peer.py" control "$work" --start 0 --end 1 --dt 1
    checkMesh -constant > log.checkMesh 2>&1 || { echo "run.sh: checkMesh failed (see $work/log.checkMesh)" >&2; exit 1; }
    postProcess -time 0 -func "flowRatePatch(name=$inlet)" > log.flowRate 2>&1 \
        || { echo "run.sh: flowRatePatch failed (see $work/log.flowRate)" >&2; exit 1; }
    END_TIME=$(python3 "$here/peer.py" residence log.checkMesh log.flowRate)
fi

# Phase 1: inject every particle (manualInjection, one parcel each) and advance 1e-12 s, so
# that OpenFOAM itself locates the parcels in the mesh and writes the cloud.
t0=1e-12
python3 "$here/peer.py" control "$work" --start 0 --end "$t0" --dt "$t0" --write-steps 1
start=$(date +%s.%N)
python3 "$here/peer.py" timed log.inject cpu.inject -- icoUncoupledKinematicParcelFoam \
    || { echo "run.sh: injection failed (see $work/log.inject)" >&2; exit 1; }
# Each parcel gets its own velocity, diameter and density (matched to its row by position).
python3 "$here/peer.py" personalise "$work" "$t0" "$particles"

# Phase 2: track on the frozen field until END_TIME.
python3 "$here/peer.py" control "$work" --start "$t0" --end "$END_TIME" --dt "$dt"
python3 "$here/peer.py" cloud "$work" --track --particles "$particles"
# It runs to END_TIME: the steps after the cloud has emptied cost little (0.3 mm airway,
# 10^4 parcels at Stk 0.1: empty from t = 0.30 s, 0.4 s of the 8.1 s of CPU time).
# track_wall_seconds is this process alone (reading the case, tracking, writing the log); its
# CPU time is split where it starts its time loop (peer.py timed: load_cpu_seconds reading
# the mesh, U, phi and the cloud; track_cpu_seconds the rest).
track_start=$(date +%s.%N)
python3 "$here/peer.py" timed log.track cpu.track -- icoUncoupledKinematicParcelFoam \
    || { echo "run.sh: tracking failed (see $work/log.track)" >&2; exit 1; }
end=$(date +%s.%N)
grep -q "^End" log.track || { echo "run.sh: icoUncoupledKinematicParcelFoam did not finish (see $work/log.track)" >&2; exit 1; }
python3 "$here/peer.py" fates "$work" "$particles" "$out/fates.csv" --wall "$(awk "BEGIN { print $end - $start }")" \
    --track-wall "$(awk "BEGIN { print $end - $track_start }")" --end-time "$END_TIME" \
    --cpu cpu.track --inject-cpu cpu.inject > "$out/summary.txt"
cat "$out/summary.txt"
