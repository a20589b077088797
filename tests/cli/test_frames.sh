#!/usr/bin/env bash
# Frames for real clients: the .pvd collection of each body lists every frame with its physical
# time (step x dt); every frame carries the same point arrays (displacement, velocity,
# contact_force, signed_distance, penetrating), NaN where a quantity was not measured; the
# surfaces are closed. Read with meshio (output.format "vtu": meshio reads VTK XML
# UnstructuredGrid, not PolyData) and, when python3-vtk9 is installed, with VTK's own XML
# readers (the default .vtp and .vtu) through the collection, as ParaView does.
# Usage: test_frames.sh HARNESS SOURCE_DIR
set -u
H="$1"; PY="${PYTHON:-/usr/bin/python3}"
"$PY" -c "import meshio" 2>/dev/null || { echo "FAIL: python3-meshio not installed (scripts/install-deps.sh installs it)"; exit 1; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
# 620 steps (contact begins at step 539), frames every 300 (0, 300, 600 and the last, 620), CGAL
# every 50 (and the last step).
for fmt in vtp vtu; do
  "$H" run cylinder_press --out "$T/$fmt" --steps 620 --set output.frames_every=300 --set output.format=$fmt \
    --set references.every=50 --set time.dt=5e-5 --quiet || { echo "FAIL: run ($fmt)"; exit 1; }
done
"$PY" - "$T" <<'PYEOF'
import base64, math, os, struct, sys, xml.etree.ElementTree as ET
import numpy as np, meshio
T = sys.argv[1]
bad = 0; checks = 0
def check(cond, what):
    global bad, checks
    checks += 1
    if not cond:
        bad += 1; print("FAIL:", what)
ARRAYS = {"displacement": 3, "velocity": 3, "contact_force": 3, "signed_distance": 1, "penetrating": 1}
def series(fmt, body):
    root = ET.parse(os.path.join(T, fmt, "frames", body + ".pvd")).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]
for body in ("layer", "cylinder"):
    s = series("vtu", body)
    check([round(t / 5e-5) for t, _ in s] == [0, 300, 600, 620], "%s.pvd times %s, expected steps 0 300 600 620" % (body, [t for t, _ in s]))
    for t, f in s:
        m = meshio.read(os.path.join(T, "vtu", "frames", f))
        step = round(t / 5e-5)
        check(set(ARRAYS) <= set(m.point_data), "%s: arrays %s" % (f, sorted(m.point_data)))
        for name, k in ARRAYS.items():
            a = np.asarray(m.point_data.get(name, np.zeros((0,))))
            check(a.shape[0] == len(m.points) and (k == 1 or a.shape[1] == k), "%s: %s shape %s" % (f, name, a.shape))
        check(len(m.cells) == 1 and m.cells[0].type == "triangle", "%s: triangles" % f)
        # Closed surface: every edge in exactly two triangles.
        tri = m.cells[0].data
        edges = {}
        for a, b, c in tri:
            for e in ((a, b), (b, c), (c, a)):
                e = tuple(sorted(e)); edges[e] = edges.get(e, 0) + 1
        check(all(v == 2 for v in edges.values()), "%s: closed surface" % f)
        sd = np.asarray(m.point_data["signed_distance"])
        measured = step in (300, 600, 620)
        check(np.all(np.isfinite(sd)) if measured else np.all(np.isnan(sd)),
              "%s: signed_distance %s at step %d" % (f, "finite" if measured else "NaN", step))
        check(np.all(np.isfinite(m.point_data["displacement"])) and np.all(np.isfinite(m.point_data["velocity"])),
              "%s: displacement, velocity finite" % f)
        if step == 0:
            check(np.abs(m.point_data["displacement"]).max() == 0.0, "%s: zero displacement at step 0" % f)
# The .vtp series: the same arrays, the same points and values as the .vtu one (parsed by hand).
def vtk_xml_arrays(path):
    root = ET.parse(path).getroot()
    out = {}
    for da in root.iter("DataArray"):
        raw = base64.b64decode(da.text.strip())
        n = struct.unpack("<Q", raw[:8])[0]
        dt = {"Float64": "<f8", "Int64": "<i8", "UInt8": "u1"}[da.get("type")]
        out[da.get("Name")] = np.frombuffer(raw[8:8 + n], dtype=dt)
    return root.get("type"), out
for body in ("layer", "cylinder"):
    for (t1, f1), (t2, f2) in zip(series("vtp", body), series("vtu", body)):
        k1, a1 = vtk_xml_arrays(os.path.join(T, "vtp", "frames", f1))
        k2, a2 = vtk_xml_arrays(os.path.join(T, "vtu", "frames", f2))
        check(k1 == "PolyData" and k2 == "UnstructuredGrid" and t1 == t2, "%s: kinds %s %s" % (f1, k1, k2))
        for name in list(ARRAYS) + ["Points", "connectivity"]:
            check(np.array_equal(a1[name], a2[name], equal_nan=True), "%s: %s differs between .vtp and .vtu" % (f1, name))
# Contact force: the forces on all nodes of a step sum to zero (action and reaction) when only
# contact acts through them; check the sum over both bodies' surfaces is small against the largest.
f = [np.asarray(meshio.read(os.path.join(T, "vtu", "frames", b + "_000620.vtu")).point_data["contact_force"]) for b in ("layer", "cylinder")]
tot = f[0].sum(axis=0) + f[1].sum(axis=0)
peak = max(np.abs(f[0]).max(), np.abs(f[1]).max())
check(peak > 0, "a contact force acts at the last step")
check(np.all(np.isfinite(tot)) and (peak == 0 or np.abs(tot).max() <= 1e-9 * max(1.0, peak) * (len(f[0]) + len(f[1]))),
      "contact forces sum to %s (largest %g)" % (tot, peak))
try:
    import vtk
except ImportError:
    vtk = None
    print("python3-vtk9 not installed: VTK reader part skipped")
if vtk is not None:
    for fmt in ("vtp", "vtu"):
        r = vtk.vtkPVDReader() if hasattr(vtk, "vtkPVDReader") else None
        for body in ("layer", "cylinder"):
            for t, f in series(fmt, body):
                rd = vtk.vtkXMLPolyDataReader() if fmt == "vtp" else vtk.vtkXMLUnstructuredGridReader()
                rd.SetFileName(os.path.join(T, fmt, "frames", f)); rd.Update()
                out = rd.GetOutput()
                check(out.GetNumberOfPoints() > 0 and out.GetNumberOfCells() > 0, "VTK reads %s" % f)
                for name in ARRAYS:
                    check(out.GetPointData().GetArray(name) is not None, "VTK: %s has %s" % (f, name))
print("%d passed, %d failed" % (checks - bad, bad))
sys.exit(1 if bad else 0)
PYEOF
