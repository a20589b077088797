#!/usr/bin/env bash
# The scene format's JSON Schema (experiments/scene.schema.json) agrees with the loader
# (core/scene/: the key table, core/scene/keys.cpp, that both come from):
#  (a) `harness schema` prints it (compared as parsed JSON);
#  (b) every bundled scene, every valid scene of the fuzz corpus and every complete scene written
#      inline in the tests is valid by the schema and accepted by the loader (`harness list`
#      loads the file as it is; `harness run --steps 0` loads and builds it, exit 0);
#  (c) structural bad inputs (unknown key, wrong type, missing key, value out of range), each one
#      mutation of a bundled scene, are rejected by the schema and by the loader (exit 2, the
#      message naming the mutated key path); a few edge values both accept.
# Checks the schema cannot express (docs/scenes.md, "JSON Schema") are not tested here.
# Usage: test_schema.sh HARNESS SOURCE_DIR. Exit 77 (skipped) without python3-jsonschema.
set -u
H="$1"; SRC="$2"; PY="${PYTHON:-/usr/bin/python3}"
if ! "$PY" -c 'import jsonschema' 2>/dev/null; then
  echo "SKIP: $PY has no jsonschema module (python3-jsonschema)"
  exit 77
fi
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
"$PY" - "$H" "$SRC" "$T" <<'PYEOF'
import copy, glob, json, os, re, subprocess, sys
import jsonschema

H, SRC, T = sys.argv[1:4]
SRC = os.path.abspath(SRC)
if os.sep in H:
    H = os.path.abspath(H)
passed = failed = 0


def result(ok, what):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
        print("FAIL: " + what)


def harness(args, env=None, timeout=300):
    """(exit status, stdout, stderr) of HARNESS ARGS."""
    e = dict(os.environ)
    e.pop("HARNESS_SCENES", None)
    e.update(env or {})
    try:
        p = subprocess.run([H] + args, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                           env=e, timeout=timeout)
    except subprocess.TimeoutExpired:
        return 124, "", "timed out after %d s" % timeout
    except OSError as ex:
        return 127, "", str(ex)
    return p.returncode, p.stdout, p.stderr.strip()


def first_line(s):
    return s.splitlines()[0] if s else "(no message)"


# ---- the schema itself ------------------------------------------------------------------------
schema_file = os.path.join(SRC, "experiments", "scene.schema.json")
try:
    with open(schema_file) as f:
        schema = json.load(f)
    jsonschema.Draft202012Validator.check_schema(schema)
    ok = schema.get("$schema") == "https://json-schema.org/draft/2020-12/schema"
    result(ok, "experiments/scene.schema.json: $schema is not draft 2020-12")
except (OSError, ValueError, jsonschema.exceptions.SchemaError) as ex:
    result(False, "experiments/scene.schema.json is not a valid draft 2020-12 schema: %s" % str(ex).splitlines()[0])
    print("%d passed, %d failed" % (passed, failed))
    sys.exit(1)
validator = jsonschema.Draft202012Validator(schema)

# ---- (a) harness schema prints it ---------------------------------------------------------------
rc, out, err = harness(["schema"], timeout=60)
if rc != 0:
    result(False, "harness schema: exit %d (%s); expected the contents of experiments/scene.schema.json"
           % (rc, first_line(err)))
else:
    try:
        printed = json.loads(out)
        result(printed == schema, "harness schema: output differs from experiments/scene.schema.json "
               "(rebuild harness: the schema is embedded at build time)")
    except ValueError as ex:
        result(False, "harness schema: output is not JSON (%s)" % ex)


def schema_errors(doc):
    return list(validator.iter_errors(doc))


def fmt_errors(errs):
    return "; ".join("%s: %s" % (".".join(map(str, e.absolute_path)) or "(top level)", e.message[:120])
                     for e in errs[:3])


def mesh_links(d):
    """Mesh paths of the corpus ("off/cube.off") resolve in d as they do in tests/fuzz/corpus/."""
    os.makedirs(d, exist_ok=True)
    for sub in ("off", "obj"):
        link = os.path.join(d, sub)
        if not os.path.lexists(link):
            os.symlink(os.path.join(SRC, "tests", "fuzz", "corpus", sub), link)


def apply_set(doc, key, value):
    """As apply_override (core/scene/document.cpp): a dotted path with list indices, missing objects made."""
    try:
        v = json.loads(value)
    except ValueError:
        v = value  # a bare word is a string
    parts = key.split(".")
    node = doc
    for p in parts[:-1]:
        node = node[int(p)] if isinstance(node, list) else node.setdefault(p, {})
    if isinstance(node, list):
        node[int(parts[-1])] = v
    else:
        node[parts[-1]] = v


# ---- (b) valid scenes -----------------------------------------------------------------------------
VALID = os.path.join(T, "valid")
mesh_links(VALID)
valid = {}  # stem -> (what, document, text given to the loader)


def add_valid(stem, what, doc, text=None):
    valid[stem] = (what, doc, text if text is not None else json.dumps(doc, indent=1))


for f in sorted(glob.glob(os.path.join(SRC, "experiments", "scenes", "*.json")) +
                glob.glob(os.path.join(SRC, "experiments", "scenes", "hard", "*.json")) +
                glob.glob(os.path.join(SRC, "experiments", "scenes", "bullet", "*.json"))):
    rel = os.path.relpath(f, os.path.join(SRC, "experiments", "scenes"))
    with open(f) as fh:
        text = fh.read()
    add_valid("bundled_" + rel[:-5].replace("/", "_"), "experiments/scenes/" + rel, json.loads(text), text)

# The fuzz corpus: leading "#set KEY=JSON" lines are overrides. bad_* and regress_* are bad inputs:
# the structural ones are cases of (c) below, the others fail where the schema cannot look (a
# duplicate key, malformed JSON, the stability guard, a mesh file, an empty selection, a --set value).
CORPUS_BAD = {"bad_unknown_key.json": "time.foo", "regress_seed_u64.json": "seed"}
corpus_bad = []
for f in sorted(glob.glob(os.path.join(SRC, "tests", "fuzz", "corpus", "scene", "*.json"))):
    base = os.path.basename(f)
    with open(f) as fh:
        lines = fh.read().split("\n")
    sets = [l[5:].strip() for l in lines if l.startswith("#set ")]
    text = "\n".join(l for l in lines if not l.startswith("#set "))
    if base.startswith(("bad_", "regress_")):
        if base in CORPUS_BAD:
            corpus_bad.append((base, json.loads(text), CORPUS_BAD[base]))
        continue
    try:
        doc = json.loads(text)
        for kv in sets:
            k, v = kv.split("=", 1)
            apply_set(doc, k, v)
    except (ValueError, LookupError, TypeError) as ex:
        result(False, "valid tests/fuzz/corpus/scene/%s: cannot read it (%s)" % (base, ex))
        continue
    add_valid("corpus_" + base[:-5], "tests/fuzz/corpus/scene/" + base, doc, None if sets else text)

# Complete scenes written inline in the tests: C++ raw strings and shell variables (good='{...}').
for f in sorted(glob.glob(os.path.join(SRC, "tests", "**", "*.cpp"), recursive=True) +
                glob.glob(os.path.join(SRC, "tests", "**", "*.hpp"), recursive=True) +
                glob.glob(os.path.join(SRC, "tests", "cli", "*.sh"))):
    with open(f) as fh:
        src = fh.read()
    if f.endswith(".sh"):
        found = re.finditer(r"^\w+='(\{.*\})'$", src, re.M)
    else:
        found = re.finditer(r'R"(\w*)\((.*?)\)\1"', src, re.S)
    for m in found:
        text = m.group(m.lastindex)
        try:
            doc = json.loads(text)
        except ValueError:
            continue  # a fragment, completed by the test's code
        if not (isinstance(doc, dict) and "bodies" in doc and "time" in doc):
            continue
        line = src.count("\n", 0, m.start()) + 1
        rel = os.path.relpath(f, SRC)
        add_valid("inline_%s_%d" % (re.sub(r"\W", "_", os.path.basename(f)), line), "%s:%d" % (rel, line), doc, text)

for stem, (what, doc, text) in valid.items():
    with open(os.path.join(VALID, stem + ".json"), "w") as fh:
        fh.write(text)

# The loader as it is (no override): `harness list` loads every scene of $HARNESS_SCENES.
rc, out, err = harness(["list"], env={"HARNESS_SCENES": VALID})
listed = {}
for line in out.splitlines():
    parts = line.split(None, 1)
    if parts:
        listed[parts[0]] = parts[1] if len(parts) > 1 else ""
result(rc == 0, "harness list (HARNESS_SCENES=valid scenes): exit %d (%s)" % (rc, first_line(err)))

for stem, (what, doc, text) in sorted(valid.items()):
    problems = []
    errs = schema_errors(doc)
    if errs:
        problems.append("schema: " + fmt_errors(errs))
    desc = listed.get(stem)
    if desc is None:
        problems.append("loader: not in harness list")
    elif desc.startswith("(invalid"):
        problems.append("loader: " + desc)
    path = os.path.join(VALID, stem + ".json")
    rc, _, err = harness(["run", path, "--steps", "0", "--out", os.path.join(T, "out_" + stem), "--quiet"])
    if rc != 0:
        problems.append("run --steps 0: exit %d (%s)" % (rc, first_line(err)))
    result(not problems, "valid %s: %s" % (what, " | ".join(problems)))

# ---- (c) bad inputs, and edge values both accept ------------------------------------------------
BAD = os.path.join(T, "bad")
mesh_links(BAD)


def load(rel):
    with open(os.path.join(SRC, rel)) as fh:
        return json.load(fh)


def cheap(doc):
    """The same scene made cheap to run should the loader accept it: one step, no settling, no
    reference solvers, no frames (every change a valid value)."""
    d = copy.deepcopy(doc)
    d["time"]["steps"] = 1
    d["time"].pop("settle", None)
    d["references"] = {"solvers": []}
    d["output"] = {"frames_every": 0}
    return d


BASES = {
    # bodies.0 layer: box, youngs_modulus, pins; bodies.1 cylinder: volume, drivers; contact: penalty
    "cyl": cheap(load("experiments/scenes/cylinder_press.json")),
    # bodies.1 implant: ellipsoid shell, youngs_modulus + thickness, pressure, a box pin
    "imp": cheap(load("experiments/scenes/implant_expansion.json")),
    # bodies.0/1: volume-filled spheres with initial velocities
    "sph": cheap(load("experiments/scenes/sphere_collision.json")),
    # contacts.0.force: a constant force (a number)
    "f100": cheap(load("experiments/scenes/hard/force_100x.json")),
    # bodies.0/1: meshes (paths relative to the corpus, linked into the bad/ folder)
    "mesh": cheap(load("tests/fuzz/corpus/scene/mesh_bodies.json")),
}

DEL = object()


def walk(doc, path):
    parts = path.split(".")
    node = doc
    for p in parts[:-1]:
        node = node[int(p)] if isinstance(node, list) else node[p]
    last = parts[-1]
    return node, (int(last) if isinstance(node, list) else last)


def mutate(base, ops):
    d = copy.deepcopy(BASES[base])
    for op in ops:
        if callable(op):
            d = op(d)
            continue
        path, value = op
        node, key = walk(d, path)
        if value is DEL:
            del node[key]
        else:
            node[key] = value
    return d


# (name, base, the key path the loader names, mutations: (path, value | DEL) or doc -> doc)
B = []
def bad(name, base, where, *ops):
    B.append((name, base, where, ops))

# unknown keys
bad("unknown key at top level", "cyl", "colour", ("colour", 1))
bad("$schema key in a scene", "cyl", "$schema", ("$schema", "scene.schema.json"))
bad("unknown key in time", "cyl", "time.foo", ("time.foo", 1))
bad("unknown key in time.settle", "cyl", "time.settle.window", ("time.settle", {"max_steps": 10, "window": 5}))
bad("unknown key in a body", "cyl", "bodies.0.colour", ("bodies.0.colour", "red"))
bad("unknown key in a shape", "cyl", "bodies.1.shape.radus", ("bodies.1.shape.radus", 1))
bad("another type's key in a cylinder", "cyl", "bodies.1.shape.radii", ("bodies.1.shape.radii", [1, 1, 1]))
bad("another type's key in a box", "cyl", "bodies.0.shape.center", ("bodies.0.shape.center", [0, 0, 0]))
bad("another type's key in a sphere", "sph", "bodies.0.shape.length", ("bodies.0.shape.length", 0.1))
bad("another type's key in an ellipsoid", "imp", "bodies.1.shape.radius", ("bodies.1.shape.radius", 0.1))
bad("another type's key in a mesh", "mesh", "bodies.0.shape.radius", ("bodies.0.shape.radius", 0.1))
bad("unknown key in material", "cyl", "bodies.0.material.poisson", ("bodies.0.material.poisson", 0.3))
bad("unknown key in a selection", "cyl", "bodies.0.pins.0.colour", ("bodies.0.pins.0.colour", 1))
bad("unknown key in a selection box", "cyl", "bodies.1.drivers.0.select.box.mid",
    ("bodies.1.drivers.0.select.box.mid", [0, 0, 0]))
bad("unknown key in a driver", "cyl", "bodies.1.drivers.0.speed", ("bodies.1.drivers.0.speed", 1))
bad("unknown key in a load", "cyl", "bodies.0.loads.0.torque",
    ("bodies.0.loads", [{"select": {"all": True}, "force": [0, 0, -1], "torque": [0, 0, 0]}]))
bad("unknown key in pressure", "imp", "bodies.1.pressure.rate", ("bodies.1.pressure.rate", 1))
bad("unknown key in a contact", "cyl", "contacts.0.friction", ("contacts.0.friction", 0.5))
bad("unknown key in a penalty force", "cyl", "contacts.0.force.damping", ("contacts.0.force.damping", 1))
bad("unknown key in references", "cyl", "references.solver", ("references.solver", ["cgal"]))
bad("unknown key in output", "cyl", "output.frames", ("output.frames", 10))
# wrong types
bad("string for dt", "cyl", "time.dt", ("time.dt", "5e-5"))
bad("fraction for steps", "cyl", "time.steps", ("time.steps", 2.5))
bad("number for settle", "cyl", "time.settle", ("time.settle", 5))
bad("string for seed", "cyl", "seed", ("seed", "1"))
bad("number for name", "cyl", "name", ("name", 7))
bad("number for a body name", "cyl", "bodies.0.name", ("bodies.0.name", 7))
bad("object for effects", "cyl", "effects", ("effects", {"springs": True}))
bad("number in effects", "cyl", "effects.1", ("effects", ["springs", 3]))
bad("list of 2 for gravity", "cyl", "gravity", ("gravity", [0, -9.81]))
bad("list of 4 for a velocity", "sph", "bodies.0.velocity", ("bodies.0.velocity", [0, 0, 0, 0]))
bad("string in a vector", "sph", "bodies.1.velocity.0", ("bodies.1.velocity", ["0", 0, 0]))
bad("object for bodies", "cyl", "bodies", lambda d: dict(d, bodies={"layer": d["bodies"][0]}))
bad("a list for the scene", "cyl", "(top level)", lambda d: [d])
bad("null for material", "cyl", "bodies.0.material", ("bodies.0.material", None))
bad("object for pins", "cyl", "bodies.0.pins", ("bodies.0.pins", {"side": "-z"}))
bad("string for a boolean", "cyl", "contacts.0.two_sided", ("contacts.0.two_sided", "yes"))
bad("number for a boolean", "cyl", "references.volume", ("references.volume", 1))
bad("string for trajectory", "cyl", "output.trajectory", ("output.trajectory", "yes"))
bad("fraction in cells", "cyl", "bodies.0.shape.cells.2", ("bodies.0.shape.cells.2", 4.5))
bad("all: false", "cyl", "bodies.0.pins.0.all", ("bodies.0.pins.0", {"all": False}))
bad("two kinds in a selection", "cyl", "bodies.0.pins.0", ("bodies.0.pins.0", {"side": "-z", "all": True}))
bad("empty selection object", "cyl", "bodies.0.pins.0", ("bodies.0.pins.0", {}))
bad("string other than auto for force", "cyl", "contacts.0.force", ("contacts.0.force", "strong"))
bad("null for force", "cyl", "contacts.0.force", ("contacts.0.force", None))
bad("list for force", "cyl", "contacts.0.force", ("contacts.0.force", [500]))
bad("string other than auto for voxel_size", "cyl", "contacts.0.voxel_size", ("contacts.0.voxel_size", "big"))
bad("string other than auto for cell_size", "cyl", "contacts.0.cell_size", ("contacts.0.cell_size", "small"))
bad("number for a contact host", "cyl", "contacts.0.host", ("contacts.0.host", 0))
bad("object for a mesh path", "mesh", "bodies.0.shape.path", ("bodies.0.shape.path", {"file": "off/cube.off"}))
# missing required keys
bad("missing bodies", "cyl", "bodies", ("bodies", DEL))
bad("missing time", "cyl", "time", ("time", DEL))
bad("missing time.dt", "cyl", "time.dt", ("time.dt", DEL))
bad("missing time.steps", "cyl", "time.steps", ("time.steps", DEL))
bad("missing settle.max_steps", "cyl", "time.settle.max_steps", ("time.settle", {"tolerance": 1e-3}))
bad("missing body name", "cyl", "bodies.0.name", ("bodies.0.name", DEL))
bad("missing body shape", "cyl", "bodies.0.shape", ("bodies.0.shape", DEL))
bad("missing shape type", "cyl", "bodies.0.shape.type", ("bodies.0.shape.type", DEL))
bad("missing box max", "cyl", "bodies.0.shape.max", ("bodies.0.shape.max", DEL))
bad("missing box cells", "cyl", "bodies.0.shape.cells", ("bodies.0.shape.cells", DEL))
bad("missing sphere radius", "sph", "bodies.0.shape.radius", ("bodies.0.shape.radius", DEL))
bad("missing ellipsoid radii", "imp", "bodies.1.shape.radii", ("bodies.1.shape.radii", DEL))
bad("missing cylinder length", "cyl", "bodies.1.shape.length", ("bodies.1.shape.length", DEL))
bad("missing mesh path", "mesh", "bodies.0.shape.path", ("bodies.0.shape.path", DEL))
bad("missing shell thickness", "imp", "bodies.1.material.thickness", ("bodies.1.material.thickness", DEL))
bad("missing selection box min", "cyl", "bodies.1.drivers.0.select.box.min", ("bodies.1.drivers.0.select.box.min", DEL))
bad("missing driver select", "cyl", "bodies.1.drivers.0.select", ("bodies.1.drivers.0.select", DEL))
bad("missing driver velocity", "cyl", "bodies.1.drivers.0.velocity", ("bodies.1.drivers.0.velocity", DEL))
bad("missing load force", "cyl", "bodies.0.loads.0.force", ("bodies.0.loads", [{"select": {"side": "+z"}}]))
bad("missing pressure to", "imp", "bodies.1.pressure.to", ("bodies.1.pressure.to", DEL))
bad("missing contact host", "cyl", "contacts.0.host", ("contacts.0.host", DEL))
bad("missing contact guest", "cyl", "contacts.0.guest", ("contacts.0.guest", DEL))
bad("missing penalty stiffness", "cyl", "contacts.0.force.stiffness", ("contacts.0.force", {}))
# values out of range
bad("dt = 0", "cyl", "time.dt", ("time.dt", 0))
bad("dt < 0", "cyl", "time.dt", ("time.dt", -5e-5))
bad("dt > 1000", "cyl", "time.dt", ("time.dt", 1001))
bad("negative steps", "cyl", "time.steps", ("time.steps", -5))
bad("steps > 2e9", "cyl", "time.steps", ("time.steps", 3000000000))
bad("settle tolerance 0", "cyl", "time.settle.tolerance", ("time.settle", {"tolerance": 0, "max_steps": 10}))
bad("settle tolerance > 1", "cyl", "time.settle.tolerance", ("time.settle", {"tolerance": 2, "max_steps": 10}))
bad("settle max_steps 0", "cyl", "time.settle.max_steps", ("time.settle", {"max_steps": 0}))
bad("seed above long long", "cyl", "seed", ("seed", 2 ** 63))
bad("unknown integrator", "cyl", "time.integrator", ("time.integrator", "rk4"))
bad("unknown guard", "cyl", "time.guard", ("time.guard", "ignore"))
bad("unknown effect", "cyl", "effects.1", ("effects", ["springs", "magic"]))
bad("effect listed twice", "cyl", "effects.1", ("effects", ["springs", "springs"]))
bad("no bodies", "cyl", "bodies", ("bodies", []))
bad("empty body name", "cyl", "bodies.0.name", ("bodies.0.name", ""))
bad("unknown shape type", "cyl", "bodies.0.shape.type", ("bodies.0.shape.type", "torus"))
bad("cells 0", "cyl", "bodies.0.shape.cells.0", ("bodies.0.shape.cells.0", 0))
bad("cells 1001", "cyl", "bodies.0.shape.cells.1", ("bodies.0.shape.cells.1", 1001))
bad("cells of length 2", "cyl", "bodies.0.shape.cells", ("bodies.0.shape.cells", [20, 20]))
bad("box fill shell", "cyl", "bodies.0.shape.fill", ("bodies.0.shape.fill", "shell"))
bad("unknown fill", "cyl", "bodies.1.shape.fill", ("bodies.1.shape.fill", "hollow"))
bad("sphere radius 0", "sph", "bodies.0.shape.radius", ("bodies.0.shape.radius", 0))
bad("subdivisions 8", "sph", "bodies.0.shape.subdivisions", ("bodies.0.shape.subdivisions", 8))
bad("subdivisions -1", "sph", "bodies.0.shape.subdivisions", ("bodies.0.shape.subdivisions", -1))
bad("ellipsoid radius 0", "imp", "bodies.1.shape.radii", ("bodies.1.shape.radii.2", 0))
bad("cylinder radius < 0", "cyl", "bodies.1.shape.radius", ("bodies.1.shape.radius", -0.01))
bad("cylinder length 0", "cyl", "bodies.1.shape.length", ("bodies.1.shape.length", 0))
bad("cylinder axis zero", "cyl", "bodies.1.shape.axis", ("bodies.1.shape.axis", [0, 0, 0]))
bad("segments 2", "cyl", "bodies.1.shape.segments", ("bodies.1.shape.segments", 2))
bad("rings 0", "cyl", "bodies.1.shape.rings", ("bodies.1.shape.rings", 0))
bad("empty mesh path", "mesh", "bodies.0.shape.path", ("bodies.0.shape.path", ""))
bad("mesh scale 0", "mesh", "bodies.0.shape.scale", ("bodies.0.shape.scale", 0))
bad("negative density", "cyl", "bodies.0.material.density", ("bodies.0.material.density", -1000))
bad("density 0", "cyl", "bodies.0.material.density", ("bodies.0.material.density", 0))
bad("youngs_modulus 0", "cyl", "bodies.0.material.youngs_modulus", ("bodies.0.material.youngs_modulus", 0))
bad("stiffness 0", "f100", "bodies.0.material.stiffness",
    ("bodies.0.material.youngs_modulus", DEL), ("bodies.0.material.stiffness", 0))
bad("stiffness and youngs_modulus", "cyl", "bodies.0.material", ("bodies.0.material.stiffness", 50))
bad("thickness on a box", "cyl", "bodies.0.material.thickness", ("bodies.0.material.thickness", 0.001))
bad("thickness on a filled sphere", "sph", "bodies.0.material.thickness", ("bodies.0.material.thickness", 0.001))
bad("thickness with stiffness on a shell", "imp", "bodies.1.material.thickness",
    ("bodies.1.material.youngs_modulus", DEL), ("bodies.1.material.stiffness", 100))
bad("shell thickness 0", "imp", "bodies.1.material.thickness", ("bodies.1.material.thickness", 0))
bad("unknown law", "cyl", "bodies.0.material.law", ("bodies.0.material.law", "quadratic"))
bad("nonlinearity < 0", "cyl", "bodies.0.material.nonlinearity", ("bodies.0.material.nonlinearity", -1))
bad("nonlinearity > 1e6", "cyl", "bodies.0.material.nonlinearity", ("bodies.0.material.nonlinearity", 2e6))
bad("negative damping", "cyl", "bodies.0.material.damping", ("bodies.0.material.damping", -0.1))
bad("negative mass_damping", "cyl", "bodies.0.material.mass_damping", ("bodies.0.material.mass_damping", -1))
bad("unknown side", "cyl", "bodies.0.pins.0.side", ("bodies.0.pins.0.side", "+w"))
bad("driver from_step -1", "cyl", "bodies.1.drivers.0.from_step", ("bodies.1.drivers.0.from_step", -1))
bad("driver to_step -2", "cyl", "bodies.1.drivers.1.to_step", ("bodies.1.drivers.1.to_step", -2))
bad("load ramp_steps -1", "cyl", "bodies.0.loads.0.ramp_steps",
    ("bodies.0.loads", [{"select": {"all": True}, "force": [0, 0, -1], "ramp_steps": -1}]))
bad("pressure above 1e9", "imp", "bodies.1.pressure.to", ("bodies.1.pressure.to", 2e9))
bad("pressure from below -1e9", "imp", "bodies.1.pressure.from", ("bodies.1.pressure.from", -2e9))
bad("pressure ramp_steps -1", "imp", "bodies.1.pressure.ramp_steps", ("bodies.1.pressure.ramp_steps", -1))
bad("unknown detector", "cyl", "contacts.0.detector", ("contacts.0.detector", "bvh"))
bad("unknown eliminator", "cyl", "contacts.0.eliminator", ("contacts.0.eliminator", "cone"))
bad("unknown region", "cyl", "contacts.0.region", ("contacts.0.region", "quarter"))
bad("unknown host_nodes", "cyl", "contacts.0.host_nodes", ("contacts.0.host_nodes", "inner"))
bad("margin 65", "cyl", "contacts.0.margin", ("contacts.0.margin", 65))
bad("margin -1", "cyl", "contacts.0.margin", ("contacts.0.margin", -1))
bad("voxel_size 0", "cyl", "contacts.0.voxel_size", ("contacts.0.voxel_size", 0))
bad("voxel_size > 1e6", "cyl", "contacts.0.voxel_size", ("contacts.0.voxel_size", 2e6))
bad("cell_size < 0", "cyl", "contacts.0.cell_size", ("contacts.0.cell_size", -1))
bad("separation_time 0", "cyl", "contacts.0.separation_time", ("contacts.0.separation_time", 0))
bad("negative force", "f100", "contacts.0.force", ("contacts.0.force", -1))
bad("force > 1e12", "f100", "contacts.0.force", ("contacts.0.force", 2e12))
bad("negative penalty stiffness", "cyl", "contacts.0.force.stiffness", ("contacts.0.force.stiffness", -500))
bad("unknown reference solver", "cyl", "references.solvers.1", ("references.solvers", ["cgal", "bullet"]))
bad("reference solver listed twice", "cyl", "references.solvers.1", ("references.solvers", ["cgal", "cgal"]))
bad("references.every 0", "cyl", "references.every", ("references.every", 0))
bad("negative frames_every", "cyl", "output.frames_every", ("output.frames_every", -1))
bad("unknown output format", "cyl", "output.format", ("output.format", "png"))

# Edge values the loader accepts: the schema must accept them too.
G = []
def good(name, base, *ops):
    G.append((name, base, ops))

good("time.settle null", "cyl", ("time.settle", None))
good("time.settle with defaults", "cyl", ("time.settle", {"max_steps": 1}))
good("steps 0", "cyl", ("time.steps", 0))
good("integers written as 1.0", "cyl", ("time.steps", 1.0), ("seed", 3.0))
good("largest seed", "cyl", ("seed", 2 ** 63 - 1))
good("smallest seed", "cyl", ("seed", -2 ** 63))
good("empty scene name", "cyl", ("name", ""))
good("no name, effects, contacts, references, output", "cyl",
     ("name", DEL), ("effects", DEL), ("contacts", DEL), ("references", DEL), ("output", DEL), ("gravity", DEL))
good("force 0", "cyl", ("contacts.0.force", 0))
good("force auto", "cyl", ("contacts.0.force", "auto"))
good("force absent", "cyl", ("contacts.0.force", DEL))
good("penalty stiffness 0", "cyl", ("contacts.0.force", {"stiffness": 0}))
good("voxel_size and cell_size auto", "cyl", ("contacts.0.voxel_size", "auto"), ("contacts.0.cell_size", "auto"))
good("contact options", "cyl", ("contacts.0.detector", "hash"), ("contacts.0.cell_size", 0.004),
     ("contacts.0.region", "full"), ("contacts.0.margin", 0), ("contacts.0.eliminator", "projection"),
     ("contacts.0.invert_push", True), ("contacts.0.separation_time", 0.5))
good("box fill volume", "cyl", ("bodies.0.shape.fill", "volume"))
good("select all", "cyl", ("bodies.0.pins.0", {"all": True}))
good("material {}", "cyl", ("bodies.0.material", {}))
good("a shell with stiffness, no thickness", "imp", ("bodies.1.material.youngs_modulus", DEL),
     ("bodies.1.material.thickness", DEL), ("bodies.1.material.stiffness", 100))
good("a cylinder shell with thickness", "cyl", ("bodies.1.shape.fill", "shell"), ("bodies.1.material.thickness", 0.001))
good("pressure without from", "imp", ("bodies.1.pressure.from", DEL))
good("a load", "cyl", ("bodies.0.loads", [{"select": {"side": "+z"}, "force": [0, 0, -1], "ramp_steps": 10}]))
good("driver window defaults", "cyl", ("bodies.1.drivers.0.from_step", DEL), ("bodies.1.drivers.0.to_step", DEL))
good("references every, volume, solvers", "cyl", ("references", {"solvers": ["fcl", "ccd"], "every": 5, "volume": False}))
good("output trajectory", "cyl", ("output.trajectory", True))
good("output format vtu", "cyl", ("output.format", "vtu"))

n = 0
def write_case(doc):
    global n
    n += 1
    path = os.path.join(BAD, "case_%03d.json" % n)
    with open(path, "w") as fh:
        json.dump(doc, fh, indent=1)
    return path


def path_parts(where):
    return [] if where == "(top level)" else where.split(".")


def check_bad(name, doc, where):
    problems = []
    errs = schema_errors(doc)
    if not errs:
        problems.append("schema accepts it")
    else:
        want = path_parts(where)
        def related(e):  # the error is at the mutated key, inside it or around it
            got = [str(p) for p in e.absolute_path]
            k = min(len(got), len(want))
            return got[:k] == want[:k]
        near = [e for e in errs if related(e)]
        if not near:
            problems.append("schema rejects it elsewhere: " + fmt_errors(errs))
    path = write_case(doc)
    rc, _, err = harness(["run", path, "--out", os.path.join(T, "out_bad"), "--quiet"], timeout=120)
    if rc != 2:
        problems.append("loader: exit %d, expected 2 (%s)" % (rc, first_line(err)))
    elif ("%s: %s:" % (os.path.basename(path), where)) not in err:
        problems.append("loader names another key: " + first_line(err))
    result(not problems, "bad %s [%s]: %s" % (name, where, " | ".join(problems)))


for name, base, where, ops in B:
    check_bad(name, mutate(base, ops), where)
for base, doc, where in corpus_bad:
    check_bad("tests/fuzz/corpus/scene/" + base, doc, where)

for name, base, ops in G:
    doc = mutate(base, ops)
    problems = []
    errs = schema_errors(doc)
    if errs:
        problems.append("schema: " + fmt_errors(errs))
    path = write_case(doc)
    rc, _, err = harness(["run", path, "--out", os.path.join(T, "out_good"), "--quiet"], timeout=300)
    if rc != 0:
        problems.append("loader: exit %d (%s)" % (rc, first_line(err)))
    result(not problems, "edge value %s: %s" % (name, " | ".join(problems)))

print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
PYEOF
