#!/usr/bin/env bash
# `harness run --node-order` (core/node_order.hpp): the layout is internal. The same scene run in the
# scene's order, in rcm and in morton order writes surfaces.csv and the frames in the scene's
# numbering (the same rows, the same faces, positions that differ by rounding only: the force sums
# run in another order) and records the layout in summary.json; a bad name is bad input.
# Usage: test_node_order.sh HARNESS SOURCE_DIR
set -u
H="$1"; PY="${PYTHON:-/usr/bin/python3}"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
# 300 steps of the sphere collision: the spheres approach without touching (no chatter to amplify
# the rounding), every effect of the scene on.
for o in scene rcm morton; do
  "$H" run sphere_collision --steps 300 --set 'references.solvers=[]' --node-order $o --out "$T/$o" --quiet \
    || fail "run --node-order $o exited $?"
done
"$PY" - "$T" <<'PYEOF' || fail "outputs differ between layouts"
import base64, json, struct, sys, xml.etree.ElementTree as ET
from pathlib import Path
T = Path(sys.argv[1])

def surfaces(d):
    rows = (T / d / "surfaces.csv").read_text().splitlines()
    assert rows[0].startswith("body,node,x,y,z,x0,y0,z0"), rows[0]
    return [r.split(",") for r in rows[1:]]

def vtp(path):
    out = {}
    for a in ET.parse(path).getroot().iter("DataArray"):
        raw = base64.b64decode(a.text.strip())
        n = struct.unpack("<Q", raw[:8])[0]
        fmt = "<%d%s" % (n // 8, "d" if a.get("type") == "Float64" else "q")
        out[a.get("Name")] = struct.unpack(fmt, raw[8:8 + n])
    return out

base = surfaces("scene")
for o in ("rcm", "morton"):
    s = json.loads((T / o / "summary.json").read_text())
    assert s["node_order"] == o, s["node_order"]
    rows = surfaces(o)
    assert [r[:2] for r in rows] == [r[:2] for r in base], o + ": rows not in the scene's numbering"
    assert all(r[5:8] == b[5:8] for r, b in zip(rows, base)), o + ": rest positions differ (another node in a row)"
    dx = max(abs(float(r[k]) - float(b[k])) for r, b in zip(rows, base) for k in (2, 3, 4))
    assert dx < 1e-12, "%s: surfaces.csv positions differ by %g m" % (o, dx)
    for f in sorted((T / "scene" / "frames").glob("*.vtp")):
        a, b = vtp(f), vtp(T / o / "frames" / f.name)
        assert a["connectivity"] == b["connectivity"], o + ": " + f.name + ": faces not in the scene's numbering"
        d = max(abs(p - q) for p, q in zip(a["Points"], b["Points"]))
        assert d < 1e-12, "%s: %s: points differ by %g m" % (o, f.name, d)
    print("%s: %d surface rows as the scene numbers them, largest position difference %.3g m" % (o, len(rows), dx))
s = json.loads((T / "scene" / "summary.json").read_text())
assert s["node_order"] == "scene"
PYEOF
# Bad input: exit 2, one line naming the option.
"$H" run sphere_collision --steps 1 --node-order hilbert --out "$T/bad" --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 ]] && grep -q -- "--node-order" "$T/err" || fail "bad --node-order: exit $rc: $(cat "$T/err")"
[[ ! -e "$T/bad/summary.json" ]] || fail "bad --node-order left a summary"
# The layouts the device and Bullet paths do not take: refused before anything is written.
for extra in "--device cpu" "--engine bullet"; do
  "$H" run sphere_collision --steps 1 --node-order rcm $extra --out "$T/no" --quiet 2>"$T/err"; rc=$?
  [[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 ]] && grep -q -- "--node-order" "$T/err" \
    || fail "--node-order rcm $extra: exit $rc: $(cat "$T/err")"
done
[[ ! -e "$T/no/summary.json" ]] || fail "a refused --node-order left a summary"
[[ $fails -eq 0 ]] && echo "node order: all checks passed"
[[ $fails -eq 0 ]]
