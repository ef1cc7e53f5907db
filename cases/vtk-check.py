#!/usr/bin/env python3
"""Read the ParaView files of a `pseudorigid run` with VTK's own readers and compare every
array with the run's CSV files; optionally render one frame to a PNG.

    vtk-check.py OUT_DIR [--png FILE --frame N]

OUT_DIR holds particles.pvd, vtk/particles_*.vtp, vtk/trajectories.vtp, frames.csv and
trajectories.csv. Checks:
- the .pvd lists one data set per frame of frames.csv, with the same times, in order;
- every frame file parses with vtkXMLPolyDataReader and holds the points and the arrays
  id, V (9 components, the active tensors), r1, r2, r3, flag of its frame's CSV rows;
  the files store floats as Float32 (as foamToVTK does), so each must equal the CSV's f64
  rounded to nearest f32, to the last bit (the CSV prints shortest round-trip decimals and
  both roundings are correct), and any difference is a writer bug;
- V is symmetric and its eigenvalues are r1 >= r2 >= r3 to 5e-7 relative to r1: rounding
  V's nine entries to f32 moves each eigenvalue by at most ||dV||_2 <= 3 * 2^-24 r1 (Weyl),
  r's own rounding adds 2^-24 r1, and a float64 eigensolver adds a few 1e-16;
- trajectories.vtp has one polyline per particle through that particle's rows of
  trajectories.csv, in order, with the arrays id and t.
Exits non-zero with a message on the first failure.

Rendering uses VTK's OpenGL render window, which on Debian needs an X server: run under
`xvfb-run` on a headless machine (cases/vtk-check.sh does).
"""

import csv
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader


def fail(msg):
    print(f"vtk-check: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_vtp(path):
    r = vtkXMLPolyDataReader()
    r.SetFileName(str(path))
    r.Update()
    data = r.GetOutput()
    if r.GetErrorCode() != 0 or data is None:
        fail(f"{path}: the VTK reader reports error {r.GetErrorCode()}")
    return data


def array(data, name, n_points):
    a = data.GetPointData().GetArray(name)
    if a is None:
        fail(f"array `{name}` missing")
    values = vtk_to_numpy(a)
    if len(values) != n_points:
        fail(f"array `{name}` has {len(values)} tuples, expected {n_points}")
    return values


def check_frames(out):
    rows = read_csv(out / "frames.csv")
    pvd = ET.parse(out / "particles.pvd").getroot()
    sets = pvd.findall("./Collection/DataSet")
    frames = sorted({int(r["frame"]) for r in rows} | set(range(len(sets))))
    if len(sets) != len(frames):
        fail(f"particles.pvd lists {len(sets)} data sets, frames.csv has frames {frames[:5]}...")
    arrays = 0
    for k, ds in enumerate(sets):
        mine = [r for r in rows if int(r["frame"]) == k]
        t = float(ds.get("timestep"))
        if mine and any(float(r["time"]) != t for r in mine):
            fail(f"frame {k}: .pvd time {t!r} differs from frames.csv")
        data = read_vtp(out / ds.get("file"))
        n = data.GetNumberOfPoints()
        if n != len(mine):
            fail(f"frame {k}: {n} points, frames.csv has {len(mine)} rows")
        if n == 0:
            continue
        if data.GetPointData().GetTensors() is None or data.GetPointData().GetTensors().GetName() != "V":
            fail(f"frame {k}: V is not the active tensor array")
        pts = vtk_to_numpy(data.GetPoints().GetData())
        want = lambda cols: np.array([[float(r[c]) for c in cols] for r in mine])
        single = lambda cols: want(cols).astype(np.float32)
        checks = {
            "Points": (pts, single(["x1", "x2", "x3"])),
            "id": (array(data, "id", n), want(["id"])[:, 0].astype(np.int64)),
            "V": (array(data, "V", n), single([f"V{i}{j}" for i in "123" for j in "123"])),
            "r1": (array(data, "r1", n), single(["r1"])[:, 0]),
            "r2": (array(data, "r2", n), single(["r2"])[:, 0]),
            "r3": (array(data, "r3", n), single(["r3"])[:, 0]),
            "flag": (array(data, "flag", n), want(["flag"])[:, 0].astype(np.int64)),
        }
        for name, (got, expected) in checks.items():
            if got.shape != expected.shape or got.dtype != expected.dtype or not np.array_equal(got, expected):
                fail(f"frame {k}: `{name}` differs from frames.csv (max |diff| {np.max(np.abs(got - expected))})")
            arrays += 1
        v = checks["V"][0].reshape(n, 3, 3)
        if not np.array_equal(v, np.transpose(v, (0, 2, 1))):
            fail(f"frame {k}: V is not symmetric")
        eig = np.sort(np.linalg.eigvalsh(v.astype(np.float64)), axis=1)[:, ::-1]
        r = np.stack([checks[c][0] for c in ("r1", "r2", "r3")], axis=1).astype(np.float64)
        if np.max(np.abs(eig - r) / np.max(r, axis=1, keepdims=True)) > 5e-7:
            fail(f"frame {k}: eigenvalues of V differ from r1..r3")
    return len(sets), arrays


def check_trajectories(out):
    rows = read_csv(out / "trajectories.csv")
    data = read_vtp(out / "vtk" / "trajectories.vtp")
    n = data.GetNumberOfPoints()
    if n != len(rows):
        fail(f"trajectories.vtp: {n} points, trajectories.csv has {len(rows)} rows")
    pts = vtk_to_numpy(data.GetPoints().GetData())
    if not np.array_equal(pts, np.array([[float(r[c]) for c in ("x1", "x2", "x3")] for r in rows], dtype=np.float32)):
        fail("trajectories.vtp: points differ from trajectories.csv")
    ids = array(data, "id", n)
    if not np.array_equal(ids, np.array([int(r["id"]) for r in rows])):
        fail("trajectories.vtp: `id` differs")
    if not np.array_equal(array(data, "t", n), np.array([float(r["t"]) for r in rows], dtype=np.float32)):
        fail("trajectories.vtp: `t` differs")
    lines = data.GetLines()
    offsets = vtk_to_numpy(lines.GetOffsetsArray())
    conn = vtk_to_numpy(lines.GetConnectivityArray())
    particles = list(dict.fromkeys(int(r["id"]) for r in rows))
    if len(offsets) - 1 != len(particles):
        fail(f"trajectories.vtp: {len(offsets) - 1} polylines for {len(particles)} particles")
    for line, pid in enumerate(particles):
        idx = conn[offsets[line] : offsets[line + 1]]
        expected = [i for i, r in enumerate(rows) if int(r["id"]) == pid]
        if list(idx) != expected:
            fail(f"trajectories.vtp: polyline {line} does not run through particle {pid}'s points in order")
    return len(particles)


def render(out, frame, png):
    from vtkmodules.vtkCommonColor import vtkNamedColors
    from vtkmodules.vtkFiltersCore import vtkTensorGlyph
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingCore import (
        vtkActor,
        vtkPolyDataMapper,
        vtkRenderWindow,
        vtkRenderer,
        vtkWindowToImageFilter,
    )
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL back end)

    sets = ET.parse(out / "particles.pvd").getroot().findall("./Collection/DataSet")
    ds = sets[frame]
    cloud = read_vtp(out / ds.get("file"))
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(48)
    sphere.SetPhiResolution(24)
    glyph = vtkTensorGlyph()
    glyph.SetInputData(cloud)
    glyph.SetSourceConnection(sphere.GetOutputPort())
    glyph.ExtractEigenvaluesOff()  # V maps the unit sphere onto the particle itself
    # Colour by the longest semi-axis r1: how far each particle is stretched.
    cloud.GetPointData().SetActiveScalars("r1")
    glyph.ColorGlyphsOn()
    glyph.SetColorModeToScalars()
    # The unit sphere source has radius 0.5; V maps radius-1 points to the semi-axes.
    glyph.SetScaleFactor(2.0)
    colors = vtkNamedColors()
    ellipsoids = vtkActor()
    m = vtkPolyDataMapper()
    m.SetInputConnection(glyph.GetOutputPort())
    m.SetScalarRange(cloud.GetPointData().GetArray("r1").GetRange())
    ellipsoids.SetMapper(m)
    paths = vtkActor()
    pm = vtkPolyDataMapper()
    pm.SetInputData(read_vtp(out / "vtk" / "trajectories.vtp"))
    pm.ScalarVisibilityOff()
    paths.SetMapper(pm)
    paths.GetProperty().SetColor(colors.GetColor3d("Gray"))
    paths.GetProperty().SetLineWidth(1)
    ren = vtkRenderer()
    ren.AddActor(ellipsoids)
    ren.AddActor(paths)
    ren.SetBackground(1, 1, 1)
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.AddRenderer(ren)
    win.SetSize(960, 540)
    cam = ren.GetActiveCamera()
    cam.SetPosition(0, 0, 1)
    cam.SetFocalPoint(0, 0, 0)
    cam.SetViewUp(0, 1, 0)
    glyph.Update()
    bounds = glyph.GetOutput().GetBounds()
    ren.ResetCamera(bounds)
    cam.Zoom(1.1)
    win.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.Update()
    w = vtkPNGWriter()
    w.SetFileName(str(png))
    w.SetInputConnection(grab.GetOutputPort())
    w.Write()
    # The writer reports failures (a full disk) only in its log: check the file.
    if w.GetErrorCode() != 0 or not png.exists() or png.stat().st_size == 0:
        fail(f"{png} was not written (VTK error code {w.GetErrorCode()})")
    print(f"vtk-check: rendered frame {frame} (t = {ds.get('timestep')}) to {png}")


def main(argv):
    if len(argv) < 2:
        fail(__doc__)
    out = Path(argv[1])
    frames, arrays = check_frames(out)
    particles = check_trajectories(out)
    print(
        f"vtk-check: {out}: {frames} frames ({arrays} arrays) and {particles} trajectories "
        "read by VTK equal the CSV files"
    )
    if "--png" in argv:
        png = Path(argv[argv.index("--png") + 1])
        frame = int(argv[argv.index("--frame") + 1]) if "--frame" in argv else -1
        render(out, frame, png)


if __name__ == "__main__":
    main(sys.argv)
