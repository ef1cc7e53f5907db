#!/usr/bin/env python3
"""Writes scenes/NAME-tracers.toml and scenes/NAME-spheres.toml for every swept tutorial from
one table (what a user writes by hand from the `pseudorigid::scene` key table; kept as a
generator so the choices sit side by side). Run from this directory."""

# name: fluid (label, rho, nu), injection, t_end, sphere (diameter, density), note
AIR = ("air", 1.2)
OIL = ("a viscous oil", 1000.0)
CASES = {
    "cavity": dict(fluid=OIL, nu=0.01, inject=[("disc", (0.05, 0.05, 0.005), (0, 0, 1), 0.045)],
                   t_end=2.0, sphere=(10e-6, 2500.0), why="a closed box: injected on a disc in the mid-plane; ~6 turnovers of the lid"),
    "cavityRAS": dict(fluid=AIR, nu=1e-5, inject=[("disc", (0.05, 0.05, 0.005), (0, 0, 1), 0.045)],
                      t_end=2.0, sphere=(10e-6, 1000.0), why="a closed box: injected on a disc in the mid-plane"),
    "elbow": dict(fluid=OIL, nu=0.01, inject=[("patch", "velocity-inlet-5", 571), ("patch", "velocity-inlet-6", 429)],
                  t_end=200.0, sphere=(10e-6, 2500.0), why="about 3 passes of the 64 m channel at 1 m/s; two inlets: 1 000 split in proportion to their inflow (30.0 and 22.5 m^3/s)"),
    "pitzDaily": dict(fluid=AIR, nu=1e-5, inject=[("patch", "inlet")], t_end=1.0, sphere=(10e-6, 1000.0), why="~30 passes at the inlet's 10 m/s"),
    "pitzDailyExptInlet": dict(fluid=AIR, nu=1e-5, inject=[("patch", "inlet")], t_end=1.0, sphere=(10e-6, 1000.0), why="as pitzDaily"),
    "backwardFacingStep2D": dict(fluid=AIR, nu=1.56e-5, inject=[("patch", "inlet")], t_end=1.0, sphere=(10e-6, 1000.0), why="inlet 44.2 m/s"),
    "airFoil2D": dict(fluid=AIR, nu=1e-5, inject=[("patch", "inlet")], t_end=60.0, sphere=(10e-6, 1000.0), why="freestream 26 m/s across a 470 m far field: about 3 crossings"),
    "planarContraction": dict(fluid=OIL, nu=1e-5, inject=[("patch", "inlet")], t_end=20.0, sphere=(10e-6, 2500.0), why="the field at t = 0.25; 0.22 m at a mean inflow of 0.04 m/s: about 4 passes"),
    "porousBlockage": dict(fluid=OIL, nu=5e-3, inject=[("patch", "inlet")], t_end=20.0, sphere=(10e-6, 2500.0), why="the field at t = 100"),
    "planarPoiseuille": dict(fluid=OIL, nu=0.1, inject=[("disc", (0.0, 0.5, 0.0), (0, 0, 1), 0.09)], t_end=2.0, sphere=(10e-6, 2500.0),
                             why="periodic in x, no inlet: a disc in the mid-plane z = 0 (the 1-cell slab's centre)"),
    "pipeCyclic": dict(fluid=("water", 1000.0), nu=1e-6, inject=[("patch", "inlet")], t_end=50.0, sphere=(10e-6, 2500.0), why="10 m at ~1 m/s"),
    "squareBend": dict(fluid=AIR, nu=1.5e-5, inject=[("patch", "inlet")], t_end=1.0, sphere=(10e-6, 1000.0), why="inlet 10 m/s, ~1.5 m of duct"),
    "TJunction": dict(fluid=AIR, nu=1e-5, inject=[("patch", "inlet")], t_end=2.0, sphere=(10e-6, 1000.0), why="the field at t = 1.5 (the tutorial's end) held steady"),
    "wedgePipe": dict(fluid=AIR, nu=1e-5, inject=[("patch", "inlet")], t_end=100.0, sphere=(10e-6, 1000.0), why="0.2 m at 0.01 m/s mean"),
}

def region(r):
    if r[0] == "patch":
        return f'{{ type = "patch", name = "{r[1]}" }}'
    _, c, nrm, rad = r
    return f'{{ type = "disc", centre = [{c[0]}, {c[1]}, {c[2]}], normal = [{nrm[0]}, {nrm[1]}, {nrm[2]}], radius = {rad} }}'

for name, c in CASES.items():
    label, rho = c["fluid"]
    mu = rho * c["nu"]
    for kind in ("tracers", "spheres"):
        if kind == "tracers":
            a, rho_p, what = 1e-6, rho, "point tracers (1 µm, as dense as the fluid, overdamped `radau_iia`)"
            integ = 'type = "radau_iia"\ntol = 1e-6\ndt = 1e-6\noverdamped = true\n'
        else:
            d, rho_p = c["sphere"]
            a, what = d / 2, f"inertial rigid spheres ({d * 1e6:.0f} µm, {rho_p:.0f} kg/m^3, `auto`)"
            integ = 'type = "auto"\ntol = 1e-6\n'
        groups = ""
        for r in c["inject"]:
            count = r[2] if r[0] == "patch" and len(r) > 2 else 1000
            groups += f"""
[[particles.inject]]
count = {count}
semi_axes = [{a!r}, {a!r}, {a!r}]
fluid_velocity = true
region = {region(r[:2] if r[0] == "patch" else r)}
material = {{ law = "rigid" }}
"""
        text = f"""# OpenFOAM's {name} tutorial (tutorial sweep, docs/tutorial-sweep.md): 1 000 {what}.
# Fluid: nu = {c['nu']} m^2/s read as {label} (rho {rho} kg/m^3, mu = rho nu). {c['why']}.
seed = 57

[flow]
type = "openfoam"
case = "."

[fluid]
viscosity = {mu!r}
density = {rho!r}

[boundary]
type = "mesh"

[particles]
density = {rho_p!r}
{groups}
[integrator]
{integ}
[end]
t_end = {c['t_end']!r}

[output]
every = {c['t_end'] / 50!r}
vtk = false
"""
        open(f"scenes/{name}-{kind}.toml", "w").write(text)
print("wrote", 2 * len(CASES), "scenes")
