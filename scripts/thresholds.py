#!/usr/bin/env python3
"""Measure the bundled scenarios and write results/thresholds.json: the CI accuracy thresholds.

Each threshold is a measured value times a stated margin (at most 1.5; per scene in
SCENE_MARGIN where a smaller one is needed for force 0 to fail it):
  min_recall          = recall / 1.1          (recall := 1 when nothing ever truly penetrates)
  max_true_pen_final  = true_pen_final * 1.5
  max_depth_voxels    = max_depth_peak / voxel_size_used * 1.5
Run deliberately, after a change that is meant to move accuracy (it is NOT part of
reproduce.sh: thresholds must not follow the code automatically).
Usage: scripts/thresholds.py [--harness build/bin/harness] [--out results/thresholds.json]
"""
import argparse, json, os, subprocess, sys, tempfile

SCENES = {"sphere_collision": 800, "cylinder_press": 1200, "implant_expansion": 1500}
EVERY = 10
MARGIN = {"recall": 1.1, "true_pen_final": 1.5, "depth_voxels": 1.5}
# Tighter margins where the default removes only part of the penetration, so that the
# threshold still fails with broken elimination (force 0): cylinder_press's stable default
# leaves about two thirds of the no-contact penetration (results/tables/ablation.md).
SCENE_MARGIN = {"cylinder_press": {"true_pen_final": 1.2, "depth_voxels": 1.2}}

def run(harness, scene, steps, out):
    subprocess.run([harness, "run", scene, "--out", out, "--steps", str(steps), "--quiet",
                    "--set", "output.frames_every=0", "--set", 'references.solvers=["cgal"]',
                    "--set", "references.every=%d" % EVERY], check=True)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--harness", default="build/bin/harness")
    ap.add_argument("--out", default="results/thresholds.json")
    a = ap.parse_args()
    doc = {"about": "CI accuracy thresholds: measured value times margin; checked by the ctest "
                    "'reference:CI accuracy thresholds hold' with its broken-elimination twin. "
                    "Made by scripts/thresholds.py.",
           "every": EVERY, "margins": MARGIN, "scenes": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for scene, steps in SCENES.items():
            s = run(a.harness, scene, steps, os.path.join(tmp, scene))
            p = s["pairs"][0]
            recall = 1.0 if p["recall"] is None else p["recall"]
            depth_vox = p["max_depth_peak"] / p["voxel_size_used"]
            m = dict(MARGIN, **SCENE_MARGIN.get(scene, {}))
            doc["scenes"][scene] = {
                "steps": steps,
                "measured": {"recall": recall, "true_pen_final": p["true_pen_final"],
                             "max_depth_peak_m": p["max_depth_peak"], "voxel_size_used": p["voxel_size_used"],
                             "depth_voxels": depth_vox, "git_commit": s["git_commit"]},
                "margins": m,
                "min_recall": recall / m["recall"],
                "max_true_pen_final": int(p["true_pen_final"] * m["true_pen_final"]),
                "max_depth_voxels": depth_vox * m["depth_voxels"],
            }
    with open(a.out, "w") as f:
        json.dump(doc, f, indent=2, sort_keys=True)
        f.write("\n")
    print("wrote", a.out)

if __name__ == "__main__":
    sys.exit(main())
