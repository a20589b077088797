#!/usr/bin/env python3
"""What a step costs from Python beside the command line (docs/python.md): the same scene, the
same thread count, references and frames off, each way timed in turn, `--repeats` rounds.

  cli        `harness run SCENE --steps N` less `--steps 0` (start, build, outputs): per step
  run        harness.run(scene, steps=N) less steps=0 (the same code in the process)
  step(N)    Simulation.step(N): one call
  step() xN  Simulation.step() N times from a Python loop
  py resp    (--response) Simulation(scene, response=harness.penalty_response(k)).step(N): the
             scene's own penalty rule written in Python, called every substep
  set_v(1), set_v(all)  (--response) one set_velocities call on 1 node / every node of body 0, us
             per call (not per step; the x cli column is then meaningless)

Prints microseconds per step (medians over the rounds) and each way's ratio to the CLI's.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/step_cost.py --harness build/bin/harness
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np

import harness


def wall(fn):
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--harness", default="build/bin/harness", help="the program")
    ap.add_argument("--scenes", default="sphere_collision,cylinder_press,implant_expansion")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--response", action="store_true",
                    help="also the scene's penalty rule as a Python response, and set_velocities' cost")
    args = ap.parse_args()
    edits = {"references.solvers": [], "output.frames_every": 0}
    print(f"{'scene':<20}{'way':<12}{'us/step':>10}{'x cli':>8}")
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes.split(","):
            scene = harness.Scene.load(name).with_(**edits)  # (written below: generated shapes only)
            path = os.path.join(tmp, name + ".json")
            with open(path, "w") as f:
                json.dump(scene.to_dict(), f)

            def cli(n):
                subprocess.run([os.path.abspath(args.harness), "run", path, "--steps", str(n), "--quiet",
                                "--threads", str(args.threads), "--out", os.path.join(tmp, "o")], check=True,
                               stderr=subprocess.DEVNULL)

            def loop(n):
                sim = harness.Simulation(scene, threads=args.threads)
                t0 = time.perf_counter()
                for _ in range(n):
                    sim.step()
                return time.perf_counter() - t0

            def one(n):
                sim = harness.Simulation(scene, threads=args.threads)
                return wall(lambda: sim.step(n))

            ways = {
                "cli": lambda: wall(lambda: cli(args.steps)) - wall(lambda: cli(0)),
                "run": lambda: wall(lambda: harness.run(scene, steps=args.steps, threads=args.threads))
                - wall(lambda: harness.run(scene, steps=0, threads=args.threads)),
                "step(N)": lambda: one(args.steps),
                "step() xN": lambda: loop(args.steps),
            }
            force = scene.to_dict()["contacts"][0].get("force") if scene.contacts else None
            if args.response and isinstance(force, dict) and "stiffness" in force:
                def py(n):
                    sim = harness.Simulation(scene, threads=args.threads,
                                             response=harness.penalty_response(force["stiffness"]))
                    return wall(lambda: sim.step(n))

                def set_v(count):
                    sim = harness.Simulation(scene, threads=args.threads)
                    v = np.array(sim.velocities(0))
                    nodes = None if count is None else list(range(count))
                    rows = v if count is None else v[:count]
                    return wall(lambda: [sim.set_velocities(0, rows, nodes=nodes) for _ in range(args.steps)])

                ways["py resp"] = lambda: py(args.steps)
                ways["set_v(1)"] = lambda: set_v(1)
                ways["set_v(all)"] = lambda: set_v(None)
            times = {k: [] for k in ways}
            for _ in range(args.repeats):
                for k, fn in ways.items():
                    times[k].append(1e6 * fn() / args.steps)
            ref = statistics.median(times["cli"])
            for k, v in times.items():
                med = statistics.median(v)
                print(f"{name:<20}{k:<12}{med:>10.1f}{med / ref:>8.3f}", flush=True)


if __name__ == "__main__":
    main()
