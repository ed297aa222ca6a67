#!/usr/bin/env python3
"""Jolt on the statics probe's towers (issue 30, docs/STATICS.md).

Reads the towers peer_statics_test writes (PeerTowers.WritesTheTowersForJolt:
a JSON list of {falls, size, scene}), runs each in Jolt (PyPI culverin,
under pyenv's Python 3.12, one thread pinned to one core) for 600 frames
and judges it by the probe's rules, as PeerTowers judges lockstep and
Bullet: a tower that statics says falls must drop some cube by half its
size; one that stands must keep every cube within 2 cm of where it started,
all asleep at frame 600. Prints Jolt's counts; exits 77 (skipped) where
culverin is not installed. It asserts nothing about Jolt: the figures are
for docs/STATICS.md beside lockstep's and Bullet's.
"""
import json
import os
import subprocess
import sys

JOLT_PYTHON = os.path.expanduser("~/.pyenv/versions/3.12.1/bin/python")


def run_towers(path):
    import culverin
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    towers = json.load(open(path))
    right = {True: 0, False: 0}
    count = {True: 0, False: 0}
    for t in towers:
        s = t["scene"]
        c = s.get("constants", {})
        dt = c.get("dt", 1 / 60)
        world = culverin.PhysicsWorld(settings={"gravity": tuple(c.get("gravity", [0.0, -9.81, 0.0])),
                                                "num_threads": 1, "max_bodies": len(s["bodies"]) + 16})
        g = s["ground"]
        gm = g.get("material", {})
        world.create_body(pos=(0.0, g.get("height", 0.0), 0.0), shape=culverin.SHAPE_PLANE,
                          size=(0.0, 1.0, 0.0, 0.0), motion=culverin.MOTION_STATIC,
                          friction=gm.get("friction", 0.5), restitution=gm.get("restitution", 0.2))
        handles, start = [], []
        for b in s["bodies"]:
            m = b.get("material", {})
            handles.append(world.create_body(pos=tuple(b["position"]), rot=(0.0, 0.0, 0.0, 1.0),
                                             size=tuple(b["half_extents"]), shape=culverin.SHAPE_BOX,
                                             mass=b["mass"], friction=m.get("friction", 0.5),
                                             restitution=m.get("restitution", 0.2)))
            start.append(b["position"])
        for _ in range(600):
            world.step(dt)
        P = memoryview(world.positions)
        drop = moved = 0.0
        asleep = True
        for h, p0 in zip(handles, start):
            k = 4 * world.get_index(h)
            p = (P[k], P[k + 1], P[k + 2])
            drop = max(drop, p0[1] - p[1])
            moved = max(moved, *(abs(p[a] - p0[a]) for a in range(3)))
            asleep = asleep and not world.is_active(h)
        falls = t["falls"]
        count[falls] += 1
        if (drop >= t["size"] / 2) if falls else (moved < 0.02 and asleep):
            right[falls] += 1
    print(f"towers that statics says fall, toppled: Jolt (culverin {culverin.__version__}) "
          f"{right[True]} of {count[True]}")
    print(f"towers that statics says stand, standing and asleep: Jolt (culverin {culverin.__version__}) "
          f"{right[False]} of {count[False]}")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--worker":
        run_towers(sys.argv[2])
        return 0
    if len(sys.argv) != 2:
        print("usage: jolt_towers.py PEER_TOWERS_JSON", file=sys.stderr)
        return 2
    if not os.path.exists(JOLT_PYTHON) or subprocess.run(
            [JOLT_PYTHON, "-c", "import culverin"], capture_output=True).returncode != 0:
        print(f"jolt_towers.py: skipped: culverin not found under {JOLT_PYTHON} "
              "(pip install culverin under pyenv's Python 3.12)")
        return 77
    return subprocess.run([JOLT_PYTHON, os.path.abspath(__file__), "--worker", sys.argv[1]]).returncode


if __name__ == "__main__":
    sys.exit(main())
