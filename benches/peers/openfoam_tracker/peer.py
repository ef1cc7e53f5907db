#!/usr/bin/env python3
"""Helpers of run.sh (OpenFOAM v1912's kinematic cloud as a particle-tracking peer).

Subcommands (run.sh calls them in this order):
  setup WORK PARTICLES --nu NU --fluid-rho RHO --gravity "(gx gy gz)"
      constant/{transportProperties,g,turbulenceProperties,kinematicCloudPositions},
      system/{fvSchemes,fvSolution}, the injecting cloud dictionary.
  residence CHECKMESH_LOG FLOWRATE_LOG   print 10 V/|Q| (the tracking time).
  control WORK --start T0 --end T1 --dt DT [--write-steps K]   system/controlDict.
  personalise WORK TIME PARTICLES   give each injected parcel its row's U, d, rho.
  cloud WORK --track   the tracking cloud dictionary (no injection).
  timed LOG CPU -- COMMAND...   run an OpenFOAM solver with its output to LOG; write to CPU its
      CPU times (user + system): load_cpu_seconds up to "Starting time loop" (reading the case,
      from /proc/<pid>/stat), cpu_seconds of the whole process (its rusage).
  fates WORK PARTICLES OUT.csv --wall S [--track-wall S] --end-time T [--cpu CPU]
      [--inject-cpu CPU]   parse the patch records and the tracking log (outer steps, parcel
      outer steps, ExecutionTime) and pass on the CPU times of `timed`.

Stdlib and NumPy only.
"""

import argparse
import glob
import gzip
import math
import os
import re
import resource
import subprocess
import sys

import numpy as np

HEADER = """FoamFile
{{
    version     2.0;
    format      ascii;
    class       {cls};
    location    "{loc}";
    object      {obj};
}}
"""

# v1912 has no Stokes drag; sphereDrag is Cd = 24/Re (1 + Re^(2/3)/6) (Re < 1000). The cloud sees
# rho_f/SCALE and SCALE*nu: mu = rho_f nu is kept, so the drag force 3 pi mu d (1 + Re^(2/3)/6)
# |u - v| keeps its Stokes part while Re_p = rho_f |u - v| d / mu falls by SCALE, and the
# correction Re^(2/3)/6 by SCALE^(2/3) = 100. The only other use of rho_f in this cloud is the
# buoyancy factor (1 - rho_f/rho_p) of the gravity force (5e-4 -> 5e-7 here).
SCALE = float(os.environ.get("STOKES_SCALE", "1000"))
MAX_CO = os.environ.get("MAX_CO", "0.3")
U_INTERPOLATION = os.environ.get("U_INTERPOLATION", "cellPoint")
U_INTEGRATION = os.environ.get("U_INTEGRATION", "analytical")

PATCH_TYPES = re.compile(r"^\s*([A-Za-z0-9_.\-]+)\s*\{[^}]*?\btype\s+([A-Za-z]+)\s*;", re.M | re.S)


def write(path, cls, loc, obj, body):
    with open(path, "w") as f:
        f.write(HEADER.format(cls=cls, loc=loc, obj=obj))
        f.write(body)


def read_particles(path):
    rows = np.genfromtxt(path, delimiter=",", names=True)
    need = ["index", "x", "y", "z", "u", "v", "w", "d", "rho"]
    missing = [c for c in need if c not in rows.dtype.names]
    if missing:
        sys.exit(f"peer.py: {path} lacks columns {missing} (need {','.join(need)})")
    rows = np.atleast_1d(rows)
    idx = rows["index"].astype(np.int64)
    if len(np.unique(idx)) != len(idx):
        sys.exit(f"peer.py: {path}: repeated index")
    return rows


def patches(work):
    """(name, type) of the mesh's patches, from constant/polyMesh/boundary (always ASCII)."""
    path = os.path.join(work, "constant/polyMesh/boundary")
    # The shipped fields of reference-data keep the mesh gzipped; OpenFOAM reads either.
    if os.path.exists(path):
        text = open(path, errors="replace").read()
    else:
        with gzip.open(path + ".gz", "rt", errors="replace") as f:
            text = f.read()
    body = text[text.index("(", text.index("}")) + 1 :]
    return PATCH_TYPES.findall(body)


def cloud_dict(work, particles, track):
    rows = read_particles(particles)
    pts = patches(work)
    if not pts:
        sys.exit("peer.py: no patches in constant/polyMesh/boundary")
    # Every patch lets the parcel leave the domain; run.sh records the patch it left through and
    # classifies by the patch's type (wall: deposited, else escaped). For the fate this is the
    # same as `stick` on walls (a stuck parcel never moves again), and the cloud empties.
    interaction = "\n".join(f"            {name} {{ type escape; }}" for name, _ in pts)
    names = " ".join(name for name, _ in pts)
    d0 = float(rows["d"][0])
    rho0 = float(rows["rho"][0])
    u0 = f"({rows['u'][0]:.17g} {rows['v'][0]:.17g} {rows['w'][0]:.17g})"
    injection = "" if track else f"""
        model1
        {{
            type            manualInjection;
            massTotal       0;
            parcelBasisType fixed;
            nParticle       1;
            SOI             0;
            positionsFile   "kinematicCloudPositions";
            U0              {u0};
            sizeDistribution
            {{
                type        fixedValue;
                fixedValueDistribution {{ value {d0:.17g}; }}
            }}
        }}"""
    body = f"""
solution
{{
    active          true;
    coupled         false;
    transient       yes;
    cellValueSourceCorrection off;
    maxCo           {MAX_CO};
    sourceTerms {{ schemes {{ }} }}
    interpolationSchemes
    {{
        rho             cell;
        U               {U_INTERPOLATION};
        mu              cell;
    }}
    integrationSchemes
    {{
        U               {U_INTEGRATION};
    }}
}}

constantProperties
{{
    rho0            {rho0:.17g};
    youngsModulus   1e9;
    poissonsRatio   0.35;
}}

subModels
{{
    particleForces
    {{
        sphereDrag;
        gravity;
    }}
    injectionModels
    {{{injection}
    }}
    dispersionModel none;
    patchInteractionModel localInteraction;
    localInteractionCoeffs
    {{
        patches
        (
{interaction}
        );
    }}
    heatTransferModel none;
    surfaceFilmModel none;
    collisionModel none;
    stochasticCollisionModel none;
    radiation off;
}}

cloudFunctions
{{
    patchPostProcessing1
    {{
        type            patchPostProcessing;
        fields          (origId origProcId position d);
        maxStoredParcels 100000000;
        patches         ({names});
    }}
}}
"""
    write(os.path.join(work, "constant/kinematicCloudProperties"), "dictionary", "constant", "kinematicCloudProperties", body)


def setup(a):
    w = a.work
    rows = read_particles(a.particles)
    write(os.path.join(w, "constant/transportProperties"), "dictionary", "constant", "transportProperties",
          f"\ntransportModel  Newtonian;\nrhoInf          {a.fluid_rho / SCALE:.17g};\nnu              {a.nu * SCALE:.17g};\n"
          f"// the fluid's rho/{SCALE:g} and {SCALE:g} nu: mu = {a.fluid_rho * a.nu:.6g} Pa s kept, Re_p / {SCALE:g}"
          " (sphereDrag -> Stokes drag)\n")
    write(os.path.join(w, "constant/g"), "uniformDimensionedVectorField", "constant", "g",
          f"\ndimensions      [0 1 -2 0 0 0 0];\nvalue           {a.gravity};\n")
    write(os.path.join(w, "constant/turbulenceProperties"), "dictionary", "constant", "turbulenceProperties",
          "\nsimulationType  laminar;\n")
    pos = "\n".join(f"({x:.17g} {y:.17g} {z:.17g})" for x, y, z in zip(rows["x"], rows["y"], rows["z"]))
    write(os.path.join(w, "constant/kinematicCloudPositions"), "vectorField", "constant", "kinematicCloudPositions",
          f"\n{len(rows)}\n(\n{pos}\n)\n")
    write(os.path.join(w, "system/fvSchemes"), "dictionary", "system", "fvSchemes",
          "\nddtSchemes { default none; }\ngradSchemes { default none; }\ndivSchemes { default none; }\n"
          "laplacianSchemes { default none; }\ninterpolationSchemes { default linear; }\n"
          "snGradSchemes { default none; }\n")
    write(os.path.join(w, "system/fvSolution"), "dictionary", "system", "fvSolution", "\nsolvers { }\n")
    cloud_dict(w, a.particles, track=False)


def residence(a):
    vol = re.findall(r"Total volume = ([0-9.eE+\-]*[0-9])", open(a.checkmesh).read())
    q = re.findall(r"sum\(\w+\) of phi = ([0-9.eE+\-]+)", open(a.flowrate).read())
    if not vol or not q:
        sys.exit("peer.py: no total volume in checkMesh's log or no flow rate in flowRatePatch's log")
    tau = float(vol[-1]) / abs(float(q[-1]))
    print(f"{10.0 * tau:.9g}")


def control(a):
    steps = max(1, math.ceil((a.end - a.start) / a.dt - 1e-9))
    end = a.start + steps * a.dt
    write_steps = a.write_steps or steps
    body = f"""
application     icoUncoupledKinematicParcelFoam;
startFrom       startTime;
startTime       {a.start:.17g};
stopAt          endTime;
endTime         {end:.17g};
deltaT          {a.dt:.17g};
writeControl    timeStep;
writeInterval   {write_steps};
purgeWrite      0;
writeFormat     ascii;
writePrecision  17;
writeCompression off;
timeFormat      general;
timePrecision   12;
runTimeModifiable yes;
"""
    write(os.path.join(a.work, "system/controlDict"), "dictionary", "system", "controlDict", body)


def foam_list(path):
    """The values of an ASCII OpenFOAM list file (header, N, ( ... ))."""
    text = open(path).read()
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    head = text.index("}", text.index("FoamFile")) + 1
    return text[:head], text[head:]


def read_vectors(path):
    _, body = foam_list(path)
    return np.array([[float(v) for v in m] for m in re.findall(r"\(\s*([-+0-9.eE]+)\s+([-+0-9.eE]+)\s+([-+0-9.eE]+)\s*\)", body)])


def read_scalars(path):
    _, body = foam_list(path)
    m = re.search(r"(\d+)\s*\((.*)\)", body, re.S)
    if m is None:
        m = re.search(r"(\d+)\s*\{(.*)\}", body, re.S)  # uniform list N{value}
        return np.full(int(m.group(1)), float(m.group(2)))
    return np.array([float(v) for v in m.group(2).split()])


def rewrite(path, values, vector):
    head, _ = foam_list(path)
    if vector:
        lines = "\n".join(f"({v[0]:.17g} {v[1]:.17g} {v[2]:.17g})" for v in values)
    else:
        lines = "\n".join(f"{v:.17g}" for v in values)
    with open(path, "w") as f:
        f.write(head + f"\n\n{len(values)}\n(\n{lines}\n)\n")


def cloud_positions(cloud):
    """Parcel positions of a written cloud: `positions` ((x y z) celli per line)."""
    path = os.path.join(cloud, "positions")
    if not os.path.exists(path):
        sys.exit(f"peer.py: {path} missing (writeLagrangianPositions off?)")
    return read_vectors(path)


def match(rows, pos, tol=1e-9):
    """Row (input order) of each parcel: the input position nearest to it (within tol m).

    O(N log N): the inputs sorted along their widest coordinate (an injection plane normal to
    an axis has one coordinate all alike), each parcel compared with the inputs within tol of
    it along that coordinate only."""
    xyz = np.stack([rows["x"], rows["y"], rows["z"]], axis=1)
    pos = np.asarray(pos, dtype=float).reshape(-1, 3)
    axis = int(np.argmax(xyz.var(axis=0))) if len(xyz) else 0
    order = np.argsort(xyz[:, axis], kind="stable")
    keys = xyz[order, axis]
    lo = np.searchsorted(keys, pos[:, axis] - tol, side="left")
    hi = np.searchsorted(keys, pos[:, axis] + tol, side="right")
    which = np.full(len(pos), -1, dtype=np.int64)
    best = np.full(len(pos), np.inf)
    for k in range(int((hi - lo).max()) if len(pos) else 0):
        at = lo + k
        valid = at < hi
        cand = order[np.minimum(at, len(order) - 1)]
        d = np.sqrt(((pos - xyz[cand]) ** 2).sum(axis=1))
        better = valid & (d < best)
        which[better] = cand[better]
        best[better] = d[better]
    far = best > tol
    if far.any():
        sys.exit(f"peer.py: parcel {int(np.argmax(far))} is more than {tol:.3g} m from every input position")
    if len(np.unique(which)) != len(which):
        sys.exit("peer.py: two parcels matched one input row (repeated positions?)")
    return which


def personalise(a):
    rows = read_particles(a.particles)
    cloud = os.path.join(a.work, a.time, "lagrangian/kinematicCloud")
    pos = cloud_positions(cloud)
    orig = read_scalars(os.path.join(cloud, "origId")).astype(np.int64)
    if len(orig) != len(pos):
        sys.exit("peer.py: origId and positions differ in length")
    which = match(rows, pos)
    u = np.stack([rows["u"], rows["v"], rows["w"]], axis=1)[which]
    rewrite(os.path.join(cloud, "U"), u, vector=True)
    for field, col in (("d", "d"), ("dTarget", "d"), ("rho", "rho")):
        path = os.path.join(cloud, field)
        if os.path.exists(path):
            rewrite(path, rows[col][which], vector=False)
    # origId -> input index, for `fates`.
    with open(os.path.join(a.work, "origId.csv"), "w") as f:
        f.write("origId,index\n")
        for o, r in zip(orig, which):
            f.write(f"{o},{int(rows['index'][r])}\n")
    print(f"peer.py: {len(pos)} of {len(rows)} particles injected and matched by position", file=sys.stderr)


def proc_cpu_seconds(pid):
    """User + system CPU time of a running process (s), from /proc/<pid>/stat."""
    with open(f"/proc/{pid}/stat") as f:
        stat = f.read()
    fields = stat[stat.rindex(")") + 2 :].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def timed(a):
    """Run the command (an OpenFOAM solver) with stdout and stderr to a.log; write a.cpu:
    load_cpu_seconds, the process's CPU time when it prints "Starting time loop" (it has read
    the mesh, the fields and the cloud), and cpu_seconds, its whole CPU time (rusage, after it
    exits). Exits with the command's status."""
    command = a.command[1:] if a.command[:1] == ["--"] else a.command
    if not command:
        sys.exit("peer.py timed: no command")
    load = None
    with open(a.log, "w") as log:
        p = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        for line in p.stdout:
            log.write(line)
            if load is None and line.strip() == "Starting time loop":
                load = proc_cpu_seconds(p.pid)
        status = p.wait()
    # This process waits for no other child: its children's usage is the command's.
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    total = usage.ru_utime + usage.ru_stime
    with open(a.cpu, "w") as f:
        f.write(f"load_cpu_seconds={load if load is not None else 'nan'}\n")
        f.write(f"cpu_seconds={total:.3f}\n")
    sys.exit(status)


def cpu_values(path):
    """The key=value lines of a `timed` CPU file ({} if no file was given)."""
    if path is None:
        return {}
    with open(path) as f:
        return dict(line.strip().split("=", 1) for line in f if "=" in line)


def fates(a):
    rows = read_particles(a.particles)
    types = dict(patches(a.work))
    ids = np.genfromtxt(os.path.join(a.work, "origId.csv"), delimiter=",", names=True, dtype=np.int64)
    to_index = dict(zip(np.atleast_1d(ids["origId"]).tolist(), np.atleast_1d(ids["index"]).tolist()))
    hits = {}
    files = sorted(glob.glob(os.path.join(a.work, "postProcessing/lagrangian/kinematicCloud/patchPostProcessing1/*/*.post")))
    for path in files:
        patch = os.path.basename(path)[: -len(".post")]
        for name in types:
            if patch.endswith("_" + name) or patch == name:
                patch = name
        with open(path) as f:
            header = None
            for line in f:
                if line.startswith("#"):
                    header = line[1:].replace("(", " ").replace(")", " ").split()
                    continue
                vals = line.replace("(", " ").replace(")", " ").split()
                if not vals:
                    continue
                rec = dict(zip(header_columns(header), vals))
                o = int(float(rec["origId"]))
                t = float(rec["Time"])
                if o in hits and hits[o][1] <= t:
                    continue
                hits[o] = (patch, t, float(rec["x"]), float(rec["y"]), float(rec["z"]))
    counts = {"deposited": 0, "escaped": 0, "suspended": 0, "not_injected": 0}
    injected = set(to_index.values())
    by_index = {to_index[o]: h for o, h in hits.items()}
    unknown = set(hits) - set(to_index)
    if unknown:
        sys.exit(f"peer.py: patch records of parcels that were not injected: {sorted(unknown)[:5]}")
    with open(a.out, "w") as f:
        f.write("index,fate,patch,t,x,y,z\n")
        for r in rows:
            k = int(r["index"])
            if k in by_index:
                patch, t, x, y, z = by_index[k]
                fate = "deposited" if types.get(patch) == "wall" else "escaped"
                f.write(f"{k},{fate},{patch},{t:.9g},{x:.9g},{y:.9g},{z:.9g}\n")
            elif k in injected:
                fate = "suspended"
                f.write(f"{k},{fate},,,,,\n")
            else:
                fate = "not_injected"
                f.write(f"{k},{fate},,,,,\n")
            counts[fate] += 1
    log = open(os.path.join(a.work, "log.track")).read()
    steps = len(re.findall(r"^Time = ", log, re.M))
    exec_time = re.findall(r"ExecutionTime = ([0-9.eE+\-]+) s", log)
    # Parcel outer steps: the parcels moved in outer step k are those left after step k - 1
    # (the cloud's report after each step; phase 2 injects none), starting from the injected
    # ones. v1912 reports no finer count: each outer step of a parcel is at least one sub-step
    # (one force evaluation and analytical velocity update), more where maxCo or a face
    # crossing splits it.
    left = [int(n) for n in re.findall(r"Current number of parcels\s*=\s*(\d+)", log)]
    parcel_steps = sum([len(to_index)] + left[:-1]) if left else 0
    print(f"particles={len(rows)}")
    for k, v in counts.items():
        print(f"{k}={v}")
    print(f"end_time={a.end_time}")
    print(f"time_steps={steps}")
    times = re.findall(r"^Time = (\S+)", log, re.M)
    print(f"last_time={times[-1] if times else 0}")
    print(f"parcel_steps={parcel_steps}")
    print(f"execution_seconds={exec_time[-1] if exec_time else 'nan'}")
    print(f"wall_seconds={a.wall:.3f}")
    if a.track_wall is not None:
        print(f"track_wall_seconds={a.track_wall:.3f}")
    # CPU of the tracking process: loading the case (up to its time loop) and the rest (the
    # time loop: tracking, writing); of the injection process, whole.
    cpu = cpu_values(a.cpu)
    if cpu:
        load, total = float(cpu["load_cpu_seconds"]), float(cpu["cpu_seconds"])
        print(f"load_cpu_seconds={load:.3f}")
        print(f"track_cpu_seconds={total - load:.3f}")
    inject = cpu_values(a.inject_cpu)
    if inject:
        print(f"inject_cpu_seconds={float(inject['cpu_seconds']):.3f}")


def header_columns(header):
    """Column names of a .post line (parentheses removed): position0..2 -> x, y, z."""
    rename = {"position0": "x", "position1": "y", "position2": "z"}
    return [rename.get(h, h) for h in header or []]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("setup")
    s.add_argument("work")
    s.add_argument("particles")
    s.add_argument("--nu", type=float, required=True)
    s.add_argument("--fluid-rho", type=float, required=True)
    s.add_argument("--gravity", required=True)
    s = sub.add_parser("residence")
    s.add_argument("checkmesh")
    s.add_argument("flowrate")
    s = sub.add_parser("control")
    s.add_argument("work")
    s.add_argument("--start", type=float, required=True)
    s.add_argument("--end", type=float, required=True)
    s.add_argument("--dt", type=float, required=True)
    s.add_argument("--write-steps", type=int, default=0)
    s = sub.add_parser("personalise")
    s.add_argument("work")
    s.add_argument("time")
    s.add_argument("particles")
    s = sub.add_parser("cloud")
    s.add_argument("work")
    s.add_argument("--track", action="store_true")
    s.add_argument("--particles")
    s = sub.add_parser("fates")
    s.add_argument("work")
    s.add_argument("particles")
    s.add_argument("out")
    s.add_argument("--wall", type=float, required=True)
    s.add_argument("--track-wall", type=float)
    s.add_argument("--end-time", required=True)
    s.add_argument("--cpu")
    s.add_argument("--inject-cpu")
    s = sub.add_parser("timed")
    s.add_argument("log")
    s.add_argument("cpu")
    s.add_argument("command", nargs=argparse.REMAINDER)
    a = p.parse_args()
    if a.cmd == "cloud":
        cloud_dict(a.work, a.particles or os.path.join(a.work, "particles.csv"), a.track)
    else:
        {
            "setup": setup,
            "residence": residence,
            "control": control,
            "personalise": personalise,
            "fates": fates,
            "timed": timed,
        }[a.cmd](a)


if __name__ == "__main__":
    main()
