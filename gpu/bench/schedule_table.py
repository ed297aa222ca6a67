#!/usr/bin/env python3
"""What the GPU engine's contact schedule does to stacks, piles and sleep
(docs/GPU.md "Contact resolution"): runs scenes with body-body contacts on
the GPU engine (coloured Gauss-Seidel, the default), its Jacobi variant
(gpu-jacobi), and the float and fixed reference engines, and prints the
frame at which every body is asleep and the mean height at the end.

  gpu/bench/schedule_table.py [--lockstep build/compare/lockstep] [--frames 1500]

The piles are the benchmark's settling pile (tests/gpu/scene_helpers.hpp,
settling_pile: unit cubes in columns on a 1.2 m lattice, 0.2 m apart
vertically, the lowest 0.1 m above the ground, each turned by up to `jitter`
with the same integer generator), written as scene files.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
ENGINES = ["gpu", "gpu-jacobi", "float", "fixed"]


def settling_pile(n, height, jitter):
    """tests/gpu/scene_helpers.hpp settling_pile(n, height, false, jitter)."""
    columns = (n + height - 1) // height
    side = 1
    while side * side < columns:
        side += 1
    seed = 12345

    def rand():
        nonlocal seed
        seed = (seed * 1664525 + 1013904223) % 2**32
        return ((seed >> 16) % 2049 - 1024) / 1024.0

    bodies = []
    for k in range(n):
        column, level = divmod(k, height)
        cx, cz = column % side, column // side
        half = side // 2
        body = {"position": [(cx - half) * 1.2, 0.6 + level * 1.2, (cz - half) * 1.2]}
        jx, jy, jz = jitter * rand(), jitter * rand(), jitter * rand()
        body["orientation"] = [1.0, jx, jy, jz]
        bodies.append(body)
    return {"format": "lockstep-scene", "version": 1, "name": f"pile{n}_columns{height}",
            "frames": 600, "effects": {"sdf": False}, "bodies": bodies}


def run(lockstep, scene, engine, frames):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run.csv")
        r = subprocess.run([lockstep, "run", scene, "--engine", engine, "--frames", str(frames), "--format", "csv",
                            "--every", str(frames), "--out", out, "--no-progress"],
                           capture_output=True, text=True, check=True)
        summary = r.stdout.splitlines()[0]
        rows = [row for row in csv.DictReader(open(out)) if int(row["frame"]) == frames]
    asleep = summary.split("all asleep at frame ")[1] if "all asleep at frame" in summary else "not by %d" % frames
    ms = summary.split(" ms/step")[0].split(", ")[-1]
    heights = [float(row["py"]) for row in rows]
    return asleep, sum(heights) / len(heights), max(heights), ms


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lockstep", default=os.path.join(ROOT, "build", "compare", "lockstep"))
    ap.add_argument("--frames", type=int, default=1500)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        scenes = [("stack5", "stack5"), ("pyramid", "pyramid"),
                  ("stack20", os.path.join(ROOT, "tests", "data", "hard", "stack20.json")),
                  ("pyramid21", os.path.join(ROOT, "tests", "data", "hard", "pyramid21.json")),
                  ("pile1000 (built-in)", "pile1000"), ("bowl", "bowl")]
        for label, n, height, jitter in [("1000 cubes, columns of 4, turned by up to 0.01 (the benchmark's pile)", 1000, 4, 0.01),
                                         ("400 cubes, columns of 10, no turn", 400, 10, 0.0),
                                         ("1000 cubes, columns of 10, turned by up to 0.05", 1000, 10, 0.05)]:
            path = os.path.join(tmp, f"pile_{n}_{height}.json")
            with open(path, "w") as f:
                json.dump(settling_pile(n, height, jitter), f)
            scenes.append((label, path))
        print(f"| scene ({args.frames} frames) | " + " | ".join(f"{e}: all asleep at / mean height (m)" for e in ENGINES) + " |")
        print("|---|" + "---|" * len(ENGINES))
        for label, scene in scenes:
            cells = []
            for engine in ENGINES:
                asleep, mean, top, ms = run(args.lockstep, scene, engine, args.frames)
                cells.append(f"{asleep} / {mean:.3f}")
            print(f"| {label} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
