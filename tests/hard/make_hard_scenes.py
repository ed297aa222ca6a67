#!/usr/bin/env python3
"""Writes the hard-case catalogue tests/data/hard/*.json (docs/HARD_CASES.md).

Run from anywhere: python3 tests/hard/make_hard_scenes.py. The files are
committed; this script documents how they were made and regenerates them
byte for byte. Every value is a decimal that the loader reads exactly as
written (or a multiple of 2^-16 given as {"raw": R}), so every engine sees the
same scene.
"""
import json
import os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "hard")


def cube(pos, half=0.5, mass=1.0, **extra):
    b = {"half_extents": [half, half, half] if isinstance(half, float) else list(half),
         "mass": mass, "position": list(pos)}
    b.update(extra)
    return b


def scene(name, frames, bodies, effects=None, constants=None, ground=None):
    s = {"format": "lockstep-scene", "version": 1, "name": name, "frames": frames}
    fx = {"sdf": False}
    fx.update(effects or {})
    s["effects"] = fx
    if constants:
        s["constants"] = constants
    if ground is not None:
        s["ground"] = ground
    s["bodies"] = bodies
    return s


def write(s):
    path = os.path.join(OUT, s["name"] + ".json")
    with open(path, "w") as f:
        # One body per line keeps the files readable and diffs small.
        head = {k: v for k, v in s.items() if k != "bodies"}
        text = json.dumps(head, indent=2)[:-2]
        text += ',\n  "bodies": [\n'
        text += ",\n".join("    " + json.dumps(b, separators=(", ", ": ")) for b in s["bodies"])
        text += "\n  ]\n}\n"
        f.write(text)


def main():
    scenes = []
    # 20 unit cubes, faces touching (overlap 0: no contact until they settle).
    scenes.append(scene("stack20", 900, [cube((0.0, 0.5 + i, 0.0)) for i in range(20)]))
    # A pyramid of 6 rows (21 cubes), 2 cm gaps in a row; each upper cube rests
    # on two below, half on each.
    bodies = []
    for r in range(6):
        n = 6 - r
        for k in range(n):
            bodies.append(cube((round((2 * k - n + 1) * 0.51, 2), 0.5 + r, 0.0)))
    scenes.append(scene("pyramid21", 900, bodies))
    # 1:1000 mass ratio: 1000 kg on 1 kg (left) and 1 kg on 1000 kg (right).
    scenes.append(scene("mass_ratio", 600, [
        cube((-3.0, 0.5, 0.0), mass=1.0), cube((-3.0, 1.5, 0.0), mass=1000.0),
        cube((3.0, 0.5, 0.0), mass=1000.0), cube((3.0, 1.5, 0.0), mass=1.0),
        # a three-level 1 / 1000 / 1 sandwich
        cube((0.0, 0.5, 4.0), mass=1.0), cube((0.0, 1.5, 4.0), mass=1000.0), cube((0.0, 2.5, 4.0), mass=1.0)]))
    # 200 rad/s: a top spinning upright on the ground, and a cube tumbling
    # about a horizontal axis dropped from 1 m.
    scenes.append(scene("spin200", 1800, [
        cube((0.0, 0.5, 0.0), angular_velocity=[0.0, 200.0, 0.0]),
        cube((4.0, 1.5, 0.0), angular_velocity=[200.0, 0.0, 0.0]),
        cube((-4.0, 1.5, 0.0), angular_velocity=[120.0, -100.0, 120.0])]))
    # 50 m/s straight down onto the ground, and 50 m/s at 45 degrees.
    scenes.append(scene("impact50", 600, [
        cube((0.0, 5.0, 0.0), velocity=[0.0, -50.0, 0.0]),
        cube((-10.0, 5.0, 4.0), velocity=[35.0, -35.0, 0.0])]))
    # 8 cubes spawned overlapping by half their size (a 2x2x2 block of pitch
    # 0.5 m), and 4 cubes spawned at exactly the same point.
    bodies = []
    for i in range(2):
        for j in range(2):
            for k in range(2):
                bodies.append(cube((-3.0 + 0.5 * i, 0.75 + 0.5 * j, 0.5 * k)))
    for _ in range(4):
        bodies.append(cube((3.0, 1.0, 0.0)))
    scenes.append(scene("overlap_spawn", 900, bodies))
    # Thin: a 2 x 0.02 x 2 m plate and a 2 cm cube dropped from 1 m; a plate
    # dropped edge-on at 10 m/s.
    scenes.append(scene("thin", 600, [
        cube((0.0, 1.0, 0.0), half=(1.0, 0.01, 1.0)),
        cube((4.0, 1.0, 0.0), half=0.01),
        cube((-4.0, 2.0, 0.0), half=(0.01, 1.0, 1.0), velocity=[0.0, -10.0, 0.0])]))
    # Large: a 100 m cube (half extent 50 m, 10 t) resting on the ground and
    # a unit cube dropped onto its top face; cell size left at 4 m, so the big
    # cube covers far more than 512 cells (the broadphase's large-body path).
    scenes.append(scene("large", 600, [
        cube((0.0, 50.0, 0.0), half=50.0, mass=10000.0),
        cube((1.0, 101.0, -2.0))]))
    # Near the edge of Q16.16: a two-cube stack at (+29990, y, +29990) and a
    # single cube at (-29990, y, -29990), dropped 0.1 m.
    scenes.append(scene("q16_edge", 600, [
        cube((29990.0, 0.6, 29990.0)), cube((29990.0, 1.6, 29990.0)),
        cube((-29990.0, 0.6, -29990.0))]))
    # Past the edge: 1000 m/s along +x from x = 30000 m, no gravity, no
    # ground, no damping; x passes 32768 m in frame 167 (Q16.16 step
    # 1092000 raw per frame from raw 1966080000; INT32_MAX = 2147483647).
    scenes.append(scene("q16_overflow", 300, [cube((30000.0, 0.0, 0.0), velocity=[1000.0, 0.0, 0.0])],
                        effects={"gravity": False, "damping": False, "ground": False},
                        ground={"present": False}))
    # One cube resting on the ground (sleep on), 100,000 frames.
    scenes.append(scene("resting", 100000, [cube((0.0, 0.5, 0.0))]))
    # The same with sleep off: it must rest on contacts alone.
    scenes.append(scene("resting_awake", 100000, [cube((0.0, 0.5, 0.0))], effects={"sleep": False}))
    # Pure quaternion integration: no gravity, no ground, no damping. One cube
    # at about 200 rad/s about a skew axis, one slow.
    scenes.append(scene("spin_long", 1000000, [
        cube((0.0, 0.0, 0.0), angular_velocity=[120.0, -100.0, 120.0]),
        cube((10.0, 0.0, 0.0), angular_velocity=[0.3, 0.7, -0.2])],
        effects={"gravity": False, "damping": False, "ground": False, "contacts": False, "settling": False,
                 "sleep": False},
        ground={"present": False}))
    # A touched sleeper: a light box (0.1 kg) asleep on the ground and a heavy
    # 0.2 m cube (1.3 kg) dropped on it from 5 cm above (found by the random
    # wake property: the GPU engine pumped energy into it).
    scenes.append(scene("heavy_on_sleeper", 600, [
        cube((0.0, 0.27, 0.0), half=(0.31, 0.27, 0.25), mass=0.1, orientation=[1.0, 0.0, -1.0, 0.0], asleep=True),
        cube((-0.125, 0.69, -0.125), half=0.1, mass=1.3)]))
    # A plate (0.32 x 1.06 x 0.2 m), tilted 6 degrees off lying on its
    # narrow face, hitting the ground at 8.36 m/s with no gravity, friction,
    # restitution or settling: a plain inelastic impact, which can only lose
    # energy (found by the random scenes: the solver gained 37.7 J here).
    scenes.append(scene("plate_impact", 120, [
        cube((0.0, 0.68, 0.0), half=(0.16, 0.53, 0.1), mass=0.5, orientation=[-0.26, -0.83, -0.93, -0.24],
             velocity=[0.0, -8.36, 0.0], material={"restitution": 0.0, "friction": 0.0})],
        effects={"gravity": False, "damping": False, "friction": False, "restitution": False, "settling": False,
                 "sleep": False},
        ground={"material": {"restitution": 0.0, "friction": 0.0}}))
    # A plate (0.2 x 1.12 x 0.56 m, 0.1 kg) that starts 0.35 m deep in the
    # ground, falling at 10 m/s and spinning at 10 rad/s about each axis, with
    # restitution 0.36, no gravity and one solver pass: its corners bounce in
    # one frame and, still deep and spinning, approach again in the next
    # (found by the random scenes: warm-started, last frame's bounce struck
    # the corners now separating, +13 J, and the one pass left +2.97 J of it).
    scenes.append(scene("spin_bounce", 120, [
        cube((0.0, -0.04, 0.0), half=(0.1, 0.56, 0.28), mass=0.1, orientation=[-0.29, -0.72, -0.99, -0.85],
             velocity=[-10.0, -9.94, -10.0], angular_velocity=[-10.0, -10.0, -8.98],
             material={"restitution": 0.36, "friction": 0.0})],
        effects={"gravity": False, "damping": False, "friction": False, "settling": False, "sleep": False},
        constants={"solver_iterations": 1},
        ground={"height": 0.01, "material": {"restitution": 0.36, "friction": 0.0}}))
    # 2048 cubes of 0.1 m in one 4 m grid cell: two layers of 32 x 32 at a
    # 0.12 m pitch, the upper 1 cm above the lower.
    bodies = []
    for layer in range(2):
        y = 0.05 + layer * 0.11
        for i in range(32):
            for k in range(32):
                bodies.append(cube((round(0.1 + 0.12 * i, 2), round(y, 2), round(0.1 + 0.12 * k, 2)), half=0.05))
    scenes.append(scene("crowd_cell", 300, bodies))
    for s in scenes:
        write(s)


if __name__ == "__main__":
    main()
