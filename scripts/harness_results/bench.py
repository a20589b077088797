"""harness bench's scaling figure and tables (scripts/plot_bench.py is the command line), from
bench.csv (its columns: docs/usage.md, "Performance"):

  figures/bench_scaling.{pdf,png}  time per step against nodes per body, log-log: every method with one
                                   thread (solid) and two (dashed); the memory-bandwidth limits in grey
  tables/bench.md                  the ratios the performance targets are stated in (table), each
                                   with its target and whether it holds, the grid's memory, every time,
                                   the spatial hash's cell sweep; the GPU rows in a section of their own
  tables/bench_ratios.tex          the ratios, for the report
  tables/bench_gpu.tex             the GPU rows (device other than cpu: harness bench --device cuda)
A ratio whose rows are missing (e.g. a --quick bench has no 10^6 point) is reported as n/a.
Deterministic: fixed method order, no dates.
"""

import math
import os
import re

from . import reader, style

plt = style.pyplot()

METHODS = ["voxel_detect", "voxel_detect_eliminate", "hash_detect", "fcl", "cgal", "step", "stream_positions",
           "stream_step", "arith_floor", "pass_floor"]
# The spatial hash's cell-size sweep (bench.md only; the figure shows the automatic cell).
CELL_SWEEP = ["hash_detect_cell_x0.5", "hash_detect", "hash_detect_cell_x2", "hash_detect_cell_x4"]
STYLE = {  # colour-blind-safe (Okabe-Ito), a marker each
    "voxel_detect": ("#0072B2", "o"),
    "voxel_detect_eliminate": ("#56B4E9", "s"),
    "hash_detect": ("#E69F00", "P"),
    "fcl": ("#D55E00", "^"),
    "cgal": ("#CC79A7", "v"),
    "step": ("#009E73", "D"),
    "stream_positions": ("#999999", "."),
    "stream_step": ("#444444", "x"),
    "arith_floor": ("#444444", "+"),
    "pass_floor": ("#444444", "1"),
}
LABEL = {
    "voxel_detect": "voxel detection",
    "voxel_detect_eliminate": "voxel detection + elimination",
    "hash_detect": "spatial hashing: triangles hashed,\ninside test of every guest node",
    "fcl": "FCL: refit + all triangle pairs",
    "cgal": "CGAL: tree + inside test\nof every guest node",
    "step": "full step (springs, contact,\nintegration)",
    "stream_positions": "limit: stream over positions",
    "stream_step": "limit: stream over what\na step reads",
    "arith_floor": "limit: a square root and\na division per spring",
    "pass_floor": "limit: both ends read, a square\nroot and a division per spring",
}


def load(path, device="cpu"):
    """bench.csv's rows of one device ("cpu": the rows without a device column too; "gpu": every
    other device): counts as ints (None where empty), us_per_step a float."""
    rows = reader.read_csv(path, text=("method", "note", "device", "machine"), missing=[])
    on_cpu = lambda r: r.get("device") in (None, "", "cpu")  # noqa: E731
    rows = [r for r in rows if on_cpu(r) == (device == "cpu")]
    for r in rows:
        r["nodes"] = int(r["nodes"])
        r["threads"] = int(r["threads"])
        r["us_per_step"] = float(r["us_per_step"])
        r["bytes"] = int(r["bytes"]) if reader.present(r["bytes"]) else 0
        for k in ("host_nodes", "guest_nodes", "voxels", "reps"):
            if k in r:
                r[k] = int(r[k]) if reader.present(r[k]) else None
    return rows


def get(rows, method, nodes, threads):
    for r in rows:
        if r["method"] == method and r["nodes"] == nodes and r["threads"] == threads:
            return r
    return None


def us(rows, method, nodes, threads):
    r = get(rows, method, nodes, threads)
    return r["us_per_step"] if r else None


def per_node(rows, method, nodes, threads):
    r = get(rows, method, nodes, threads)
    if not r or not r.get("host_nodes"):
        return None
    return r["us_per_step"] / (r["host_nodes"] + r["guest_nodes"])


def ratio(a, b):
    return a / b if a is not None and b is not None and b > 0 else None


def fmt(x, digits=1):
    if x is None:
        return "n/a"
    return ("%." + str(digits) + "f") % x


def figure(rows, out_dir):
    from matplotlib.lines import Line2D
    fig, ax = plt.subplots(figsize=(style.TEXT, 3.0), layout="constrained")
    for m in METHODS:
        color, marker = STYLE[m]
        for t, ls in ((1, "-"), (2, "--")):
            pts = sorted((r["nodes"], r["us_per_step"]) for r in rows if r["method"] == m and r["threads"] == t)
            if not pts:
                continue
            lim = m.startswith("stream") or m.endswith("_floor")
            ax.plot([p[0] for p in pts], [p[1] for p in pts], ls, color=color, marker=marker,
                    markersize=3.5, linewidth=0.9 if lim else 1.2, alpha=0.85 if lim else 1.0)
    ax.set_xscale("log")
    ax.set_yscale("log")
    style.plain_log_ticks(ax.xaxis, ax.yaxis)
    ax.set_xlabel("nodes per body")
    ax.set_ylabel("time per step (µs)")
    ax.grid(True, which="major", alpha=0.4)
    methods = [m for m in METHODS if any(r["method"] == m for r in rows)]
    handles = [Line2D([], [], color=STYLE[m][0], marker=STYLE[m][1], markersize=3.5, label=LABEL[m]) for m in methods]
    handles += [Line2D([], [], color="0.3", ls="-", label="1 thread"), Line2D([], [], color="0.3", ls="--", label="2 threads")]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), ncol=1, frameon=False, borderaxespad=0.0)
    style.save(fig, os.path.join(out_dir, "figures", "bench_scaling"), width=style.TEXT)


def target_lines(name, at, value, target, ok):
    """(Markdown line, LaTeX line) of one ratio: its value, its target and whether it holds (ok: the
    target's test, None for a ratio without one)."""
    holds = "n/a" if value is None else ("-" if ok is None else ("yes" if ok(value) else "no"))
    md = "| %s | %s | %s | %s | %s |" % (name, at, fmt(value, 2), target, holds)
    tex = " & ".join([re.sub(r"10\^(\d)", r"$10^\1$", name.replace("_", "\\_")), at.replace("10^", "$10^").replace(" -> ", "$ to ") +
                      ("$" if not at.endswith("$") and "10^" in at and " -> " not in at else
                       ("$" if " -> " in at else "")),
                      fmt(value, 2), target.replace(">=", "$\\ge$").replace("<=", "$\\le$"), holds]) + " \\\\"
    return md, tex


def detection_ratios(rows, row):
    """The references against the voxel model's detection at 10^5 nodes per body, and against the
    stream over positions (their ceilings)."""
    n5 = 100000
    for t in (1, 2):
        row("FCL refit + collide / voxel detection (%dT)" % t, "10^5", ratio(us(rows, "fcl", n5, 1), us(rows, "voxel_detect", n5, t)),
            ">= 50", lambda v: v >= 50)
    for t in (1, 2):
        row("CGAL ground truth / voxel detection (%dT)" % t, "10^5", ratio(us(rows, "cgal", n5, 1), us(rows, "voxel_detect", n5, t)),
            ">= 2000", lambda v: v >= 2000)
    row("bound: FCL / stream over positions (1T)", "10^5", ratio(us(rows, "fcl", n5, 1), us(rows, "stream_positions", n5, 1)),
        "(ceiling)", None)
    row("bound: CGAL / stream over positions (1T)", "10^5", ratio(us(rows, "cgal", n5, 1), us(rows, "stream_positions", n5, 1)),
        "(ceiling)", None)


def step_ratios(rows, sizes, row):
    """The step against its physical limit, at every size: ns per spring, the ratio to the streaming
    pass over what it reads and writes (the goal at 10^3 and 10^4 nodes per body), and to the force
    pass's floor (both ends of every spring read, a square root and a division each: what any force
    pass must do); the energy audit's share."""
    for n in sizes:
        at = "10^%d" % round(math.log10(n)) if n > 0 and 10 ** round(math.log10(n)) == n else str(n)
        goal = n in (1000, 10000)
        for t in (1, 2):
            r = get(rows, "step", n, t)
            v = us(rows, "step", n, t)
            row("step: ns per spring (%dT)" % t, at, (1e3 * v / r["springs"]) if v and r and r.get("springs") else None,
                "<= 3" if t == 1 and n == 10000 else "-", (lambda v: v <= 3) if t == 1 and n == 10000 else None)
            row("step / stream over what it reads (%dT)" % t, at, ratio(v, us(rows, "stream_step", n, t)),
                "<= 3" if goal else "-", (lambda v: v <= 3) if goal else None)
            row("step / force pass floor (%dT)" % t, at, ratio(v, us(rows, "pass_floor", n, t)), "(distance)", None)
        laws = us(rows, "step_scene_laws", n, 1)
        row("step with the scenes' laws and effects / force pass floor (1T)", at,
            ratio(laws, us(rows, "pass_floor", n, 1)), "<= 2.5" if goal else "(distance)", None)
        row("step with the scenes' laws and effects / step (1T)", at, ratio(laws, us(rows, "step", n, 1)),
            "(the law's and the dashpots' cost)", None)
        row("energy audit: step_audited / step - 1 (1T)", at,
            (lambda a, b: a / b - 1.0 if a and b else None)(us(rows, "step_audited", n, 1), us(rows, "step", n, 1)),
            "<= 0.1", lambda v: v <= 0.1)


def scaling_ratios(rows, row):
    """At 10^6 nodes per body: detection and the step against their streams, the time per node
    against 10^4's, two threads against one."""
    for t in (1, 2):
        row("voxel detection / stream over positions (%dT)" % t, "10^6",
            ratio(us(rows, "voxel_detect", 1000000, t), us(rows, "stream_positions", 1000000, t)), "<= 3", lambda v: v <= 3)
    for t in (1, 2):
        row("full step / stream over what it reads (%dT)" % t, "10^6",
            ratio(us(rows, "step", 1000000, t), us(rows, "stream_step", 1000000, t)), "<= 6", lambda v: v <= 6)
    for m in ("voxel_detect", "voxel_detect_eliminate", "step"):
        for t in (1, 2):
            row("time per node, 10^6 / 10^4: %s (%dT)" % (m, t), "10^4 -> 10^6",
                ratio(per_node(rows, m, 1000000, t), per_node(rows, m, 10000, t)), "<= 1.5", lambda v: v <= 1.5)
    for m in ("voxel_detect", "voxel_detect_eliminate", "step", "stream_positions", "stream_step"):
        target = ">= 1.6" if not m.startswith("stream") else "(limit)"
        row("speed-up, 2 threads over 1: %s" % m, "10^6", ratio(us(rows, m, 1000000, 1), us(rows, m, 1000000, 2)),
            target, (lambda v: v >= 1.6) if not m.startswith("stream") else None)


def memory_lines(rows, sizes):
    """bench.md's grid memory: the `bytes` column against the region it covers."""
    lines = ["", "Grid memory (VoxelData capacity, the `bytes` column) against the region it covers: 4 bytes "
             "per voxel of the region's capacity (list head) plus 8 per listed host node (next, voxel) and 8 "
             "per 4096 of them (a chunk's voxel range); nothing per guest node or per node of other bodies:", "",
             "| nodes per body | voxels in region | grid bytes | bytes per voxel | bytes per host node |",
             "|---|---|---|---|---|"]
    for n in sizes:
        r = get(rows, "voxel_detect", n, 1)
        if r and r.get("voxels"):
            lines.append("| %d | %d | %d | %.1f | %.1f |" % (n, r["voxels"], r["bytes"], r["bytes"] / r["voxels"],
                                                            r["bytes"] / max(1, r["host_nodes"])))
    return lines


def time_lines(rows, sizes):
    """bench.md's every time per step, by method and threads."""
    lines = ["", "Every time per step (µs):", "",
             "| method | threads | " + " | ".join("%d" % n for n in sizes) + " |",
             "|---|---|" + "---|" * len(sizes)]
    for m in METHODS:
        for t in (1, 2):
            vals = [us(rows, m, n, t) for n in sizes]
            if all(v is None for v in vals):
                continue
            lines.append("| %s | %d | %s |" % (m, t, " | ".join(fmt(v) for v in vals)))
    return lines


def cell_sweep_lines(rows, sizes):
    """bench.md's spatial hash cell sweep ([] when the bench made none)."""
    if not any(r["method"] == "hash_detect_cell_x2" for r in rows):
        return []
    lines = ["", "Spatial hashing's cell size (one thread; times the automatic cell, the host's mean surface "
             "edge), µs per step, and against the voxel model's detection and CGAL:", "",
             "| cell | " + " | ".join("%d" % n for n in sizes) + " |", "|---|" + "---|" * len(sizes)]
    for m in CELL_SWEEP:
        label = {"hash_detect": "x1 (automatic)"}.get(m, m.replace("hash_detect_cell_", ""))
        lines.append("| %s | %s |" % (label, " | ".join(fmt(us(rows, m, n, 1)) for n in sizes)))
    for other in ("voxel_detect", "cgal"):
        lines.append("| hash x1 / %s | %s |" % (other, " | ".join(
            fmt(ratio(us(rows, "hash_detect", n, 1), us(rows, other, n, 1))) for n in sizes)))
    return lines


# The node order rows (harness bench: core/node_order.hpp), each timed side by side with the step
# row's layout; their ratio to it is in the note.
ORDER_ROWS = [("step_order_rcm", "rcm"), ("step_order_morton", "morton"), ("step_order_scene", "scene"),
              ("step_shuffled_order_scene", "shuffled, kept as it is"), ("step_shuffled_order_rcm", "shuffled, then rcm"),
              ("step_shuffled_order_morton", "shuffled, then morton")]
ORDER_RATIO = re.compile(r"([0-9.]+) x the step row's layout side by side")


def order_lines(rows, sizes):
    """bench.md's node order: each layout's step against the step row's, measured side by side
    (one thread; [] when the bench made no such row)."""
    found = [(m, label) for m, label in ORDER_ROWS if any(r["method"] == m for r in rows)]
    if not found:
        return []
    lines = ["", "Node order (`--node-order`, one thread): the step in another layout over the step row's, the two "
             "timed side by side (their repetitions taking turns), by nodes per body. \"shuffled\": each body's "
             "surface and interior nodes first put in a random order, as a mesh file may number them:", "",
             "| layout | " + " | ".join("%d" % n for n in sizes) + " |", "|---|" + "---|" * len(sizes)]
    for m, label in found:
        vals = []
        for n in sizes:
            r = get(rows, m, n, 1)
            hit = ORDER_RATIO.search(r.get("note", "")) if r else None
            vals.append(float(hit.group(1)) if hit else None)
        lines.append("| %s | %s |" % (label, " | ".join(fmt(v, 2) for v in vals)))
    return lines


def table(rows, out_dir, csv_path):
    """tables/bench.md (the ratios, the grid's memory, every time, the cell sweep) and
    tables/bench_ratios.tex (the ratios)."""
    sizes = sorted({r["nodes"] for r in rows})
    lines = ["# harness bench: ratios", "",
             "From `%s` (`harness bench`; medians over repetitions). Ratios of times per step; "
             "`1T`/`2T` = one/two threads. FCL and CGAL are single-threaded libraries: they are "
             "always timed with one thread." % os.path.relpath(csv_path, os.path.dirname(out_dir) or "."), "",
             "| quantity | at | value | target | holds |", "|---|---|---|---|---|"]
    tex = []

    def row(name, at, value, target, ok):
        md, tx = target_lines(name, at, value, target, ok)
        lines.append(md)
        tex.append(tx)

    detection_ratios(rows, row)
    step_ratios(rows, sizes, row)
    scaling_ratios(rows, row)
    lines += (memory_lines(rows, sizes) + time_lines(rows, sizes) + order_lines(rows, sizes) +
              cell_sweep_lines(rows, sizes))
    os.makedirs(os.path.join(out_dir, "tables"), exist_ok=True)
    path = os.path.join(out_dir, "tables", "bench.md")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("plot_bench: wrote %s" % path)
    path = os.path.join(out_dir, "tables", "bench_ratios.tex")
    with open(path, "w") as f:
        f.write("% The ratios of the performance targets (made by scripts/plot_bench.py)\n"
                "\\begin{tabular}{llrll}\n\\toprule\nquantity & at & value & target & holds \\\\\n\\midrule\n" +
                "\n".join(tex) + "\n\\bottomrule\n\\end{tabular}\n")
    print("plot_bench: wrote %s" % path)


def gpu_table(gpu, cpu, out_dir):
    """The GPU rows (harness bench --device cuda): per size the device step, a device-to-device copy
    of the bytes the CPU's stream_step counts (the step's data), their ratio, ns per spring, and the
    CPU's one-thread step of this file beside it; appended to bench.md, and bench_gpu.tex."""
    if not gpu:
        return
    sizes = sorted({r["nodes"] for r in gpu})
    device = gpu[0].get("device", "?")
    md = ["", "## On a GPU (%s)" % device, "",
          "`harness bench --device cuda` (`scripts/device_check.sh`): the device step of the bench scene (median "
          "over batches of steps, each batch waited for at its end) and one device-to-device copy of the bytes "
          "`stream_step` counts for the size (read and written once). Host: %s. Unlike the CPU's rows, whose "
          "repetitions restart from the initial state, the device steps on from it: `contacts` are those of "
          "its last step (at 10^3 nodes the penalties had pushed every contact out). The CPU's step beside it "
          "is this file's, from another machine (the shared two-core machine of the CPU bench)."
          % gpu[0].get("machine", "?"), "",
          "| nodes per body | springs | contacts | step (µs) | copy (µs) | step / copy | ns per spring | CPU step 1T (µs) | CPU / GPU |",
          "|---|---|---|---|---|---|---|---|---|"]
    tex = []
    for n in sizes:
        st, cp, c1 = get(gpu, "step", n, 1), get(gpu, "copy", n, 1), us(cpu, "step", n, 1)
        if not st:
            continue
        springs = int(st["springs"]) if reader.present(st.get("springs")) else 0
        r = st["us_per_step"] / cp["us_per_step"] if cp else None
        nsps = 1000.0 * st["us_per_step"] / springs if springs else None
        md.append("| %d | %d | %s | %s | %s | %s | %s | %s | %s |" % (
            n, springs, int(float(st["contacts"])) if reader.present(st.get("contacts")) else 0, fmt(st["us_per_step"]),
            fmt(cp["us_per_step"] if cp else None), fmt(r), fmt(nsps, 3), fmt(c1), fmt(ratio(c1, st["us_per_step"]))))
        tex.append("$10^{%d}$ & %d & %d & %s & %s & %s & %s & %s \\\\" % (
            round(math.log10(n)), springs, int(float(st["contacts"])) if reader.present(st.get("contacts")) else 0,
            fmt(st["us_per_step"]), fmt(cp["us_per_step"] if cp else None), fmt(r), fmt(nsps, 3), fmt(c1)))
    with open(os.path.join(out_dir, "tables", "bench.md"), "a") as f:
        f.write("\n".join(md) + "\n")
    path = os.path.join(out_dir, "tables", "bench_gpu.tex")
    with open(path, "w") as f:
        f.write("%% The GPU rows of bench.csv (%s; made by scripts/plot_bench.py)\n" % device +
                "\\begin{tabular}{rrrrrrrr}\n\\toprule\nnodes/body & springs & contacts & step ($\\mu$s) & copy ($\\mu$s) & "
                "step/copy & ns/spring & CPU 1T ($\\mu$s) \\\\\n\\midrule\n" + "\n".join(tex) +
                "\n\\bottomrule\n\\end{tabular}\n")
    print("plot_bench: wrote %s" % path)


def write_all(csv_path, out_dir):
    """The figure and the tables of bench.csv at csv_path into out_dir; False (nothing written) when
    it has no CPU rows."""
    rows = load(csv_path)
    if not rows:
        return False
    figure(rows, out_dir)
    table(rows, out_dir, csv_path)
    gpu_table(load(csv_path, "gpu"), rows, out_dir)
    return True
