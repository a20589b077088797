#!/usr/bin/env bash
# The frames open in VTK's legacy reader (the one ParaView uses): polydata, closed surfaces
# (no boundary or non-manifold edges), the "penetrating" point array on measured steps.
# Needs Debian's python3-vtk9 (not installed by install-deps.sh: 50 MB); skipped (77) without.
# Usage: test_vtk_reader.sh HARNESS SOURCE_DIR
set -u
H="$1"; PY="${PYTHON:-/usr/bin/python3}"
"$PY" -c "import vtk" 2>/dev/null || { echo "python3-vtk9 not installed: skipped"; exit 77; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
"$H" run cylinder_press --out "$T/run" --steps 20 --set output.frames_every=10 --quiet || exit 1
"$PY" - "$T/run/frames" <<'PYEOF'
import glob, sys, vtk
files = sorted(glob.glob(sys.argv[1] + "/*.vtk"))
bad = 0
for f in files:
    r = vtk.vtkPolyDataReader(); r.SetFileName(f); r.Update()
    pd = r.GetOutput()
    fe = vtk.vtkFeatureEdges(); fe.SetInputData(pd)
    fe.BoundaryEdgesOn(); fe.NonManifoldEdgesOn(); fe.FeatureEdgesOff(); fe.ManifoldEdgesOff(); fe.Update()
    ok = r.IsFilePolyData() and pd.GetNumberOfPolys() > 0 and fe.GetOutput().GetNumberOfLines() == 0
    if f.endswith("_000010.vtk") or f.endswith("_000020.vtk"):
        ok = ok and pd.GetPointData().GetArray("penetrating") is not None
    if not ok:
        print("FAIL:", f); bad += 1
print("%d passed, %d failed" % (len(files) - bad, bad))
sys.exit(1 if bad or not files else 0)
PYEOF
