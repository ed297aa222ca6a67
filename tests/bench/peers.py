#!/usr/bin/env python3
"""lockstep beside its peers, in one go: the same scenes (one JSON file each,
read by every engine) on Bullet and lockstep's engines (`peer_bench run`, in
process: lockstep's through make_engine, the code behind `lockstep run`) and
on Jolt (PyPI `culverin`, under Python 3.12, pinned to one core; its trajectory
measured by `peer_bench measure`), each measured by the same code: ms per
step over all frames and "busy", ms per step over frames 31-120 (1-based: the
90 steps while the cubes land and collide, before anything sleeps), both
stepping only, one thread, CPU time of the process, so that other work on a
shared machine does not count (the wall clock is in the JSON lines). Every
engine's per-frame step times reach the same summary in peer_bench:
lockstep's engines and Bullet are timed frame by frame inside `peer_bench
run`; the Jolt worker times each `world.step` the same way (process CPU time)
and hands the per-frame times to `peer_bench measure --step-times`. Then the
frame from which every body stayed asleep, columns standing
at the end (every cube within 2 cm of its stacked height and within half its
size of the column's axis) and upright (within a quarter of its size), and
the worst penetration into the ground and between two boxes (mm), over all
frames and at the last.

Scenes: pile1000 (built in: 100 columns of 10 unit cubes, tilted up to about
6 degrees) and boxfall1000 (ANCHORS.md's boxfall-1000: 10 x 10 columns of 10
unit cubes, 1 kg, 0.2 m apart horizontally and vertically, the lowest 0.1 m
above the ground, friction 0.5, restitution 0.2; here every cube is tilted by
up to 1 degree about a random axis and shifted by up to 2 cm horizontally,
seeded), 600 frames each at 60 Hz.

Usage: python3 tests/bench/peers.py [--build build] [--engines LIST] [--scenes LIST] [--frames N]
An engine NAME:N (fixed:2) runs lockstep's engine on N threads (docs/SPEC.md
7.7 "Threads"); its times are then the wall clock (CPU time sums the threads).
Writes its scene files and trajectories under BUILD/peers and prints a
Markdown table (README "Speed"): ms/step over all frames, busy ms/step
(frames 31-120), all asleep at frame, columns, penetrations."""
import argparse, json, math, os, random, subprocess, sys, time

JOLT_PYTHON = os.path.expanduser("~/.pyenv/versions/3.12.1/bin/python")
ENGINES = ["bullet", "jolt", "fixed", "float", "double", "mp", "gpu"]
SCENES = ["pile1000", "boxfall1000"]


def boxfall1000(seed=20261125):
    """ANCHORS.md's boxfall-1000 with every cube tilted up to 1 degree and
    shifted up to 2 cm horizontally (seeded)."""
    rnd = random.Random(seed)
    mat = {"restitution": 0.2, "friction": 0.5}
    bodies = []
    for level in range(10):
        for cz in range(10):
            for cx in range(10):
                while True:  # an axis uniform on the sphere
                    ax = [rnd.uniform(-1, 1) for _ in range(3)]
                    l = math.sqrt(sum(x * x for x in ax))
                    if 1e-3 < l <= 1:
                        break
                angle = math.radians(1.0) * rnd.random()
                s = math.sin(angle / 2) / l
                q = [math.cos(angle / 2)] + [x * s for x in ax]
                r, phi = 0.02 * rnd.random(), 2 * math.pi * rnd.random()
                bodies.append({"half_extents": [0.5, 0.5, 0.5], "mass": 1.0,
                               "position": [(cx - 4.5) * 1.2 + r * math.cos(phi), 0.6 + 1.2 * level,
                                            (cz - 4.5) * 1.2 + r * math.sin(phi)],
                               "orientation": q, "material": mat})
    return {"format": "lockstep-scene", "version": 1, "name": "boxfall1000", "frames": 600,
            "ground": {"present": True, "height": 0.0, "material": mat}, "bodies": bodies}


def jolt_worker(scene_path, out_path, times_path, frames):
    """Runs under Python 3.12 with culverin: steps Jolt (one thread) and writes
    the trajectory in lockstep run's CSV columns and each frame's step time
    (process CPU seconds and wall seconds, one line per frame: peer_bench's
    --step-times format); prints ms/step over all frames."""
    import culverin
    print(culverin.__version__, file=sys.stderr)
    s = json.load(open(scene_path))
    c = s.get("constants", {})
    dt = c.get("dt", 1 / 60)
    g = c.get("gravity", [0.0, -9.81, 0.0])
    n = len(s["bodies"])
    # One core: culverin runs Jolt's job system with a worker thread beside
    # the calling thread, which also runs jobs while it waits (num_threads 0
    # and 1 alike): unpinned, two threads work (pile1000: 0.93 ms per step of
    # wall clock, 1.74-1.97 ms of CPU time, some of it spent waiting). Pinned
    # to one core (the threads inherit it), CPU time and wall clock agree:
    # Jolt's single-threaded figure (1.47-1.56 ms on pile1000, 2026-11-26).
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    world = culverin.PhysicsWorld(settings={"gravity": tuple(g), "num_threads": 1, "max_bodies": n + 16})
    ground = s.get("ground", {"present": True, "height": 0.0})
    if ground.get("present", True):
        gm = ground.get("material", {})
        world.create_body(pos=(0.0, ground.get("height", 0.0), 0.0), shape=culverin.SHAPE_PLANE,
                          size=(0.0, 1.0, 0.0, 0.0), motion=culverin.MOTION_STATIC,
                          friction=gm.get("friction", 0.5), restitution=gm.get("restitution", 0.2))
    handles = []
    for b in s["bodies"]:
        q = b.get("orientation", [1, 0, 0, 0])
        qn = math.sqrt(sum(x * x for x in q))
        m = b.get("material", {})
        handles.append(world.create_body(pos=tuple(b["position"]), rot=(q[1] / qn, q[2] / qn, q[3] / qn, q[0] / qn),
                                         size=tuple(b.get("half_extents", [0.5] * 3)), shape=culverin.SHAPE_BOX,
                                         mass=b.get("mass", 1.0), friction=m.get("friction", 0.5),
                                         restitution=m.get("restitution", 0.2)))
    wall = cpu = 0.0
    with open(out_path, "w") as out, open(times_path, "w") as times:
        out.write("frame,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,asleep\n")
        for f in range(1, frames + 1):
            t0, c0 = time.perf_counter(), time.process_time()
            world.step(dt)
            c, w = time.process_time() - c0, time.perf_counter() - t0
            cpu += c
            wall += w
            times.write(f"{c:.9f} {w:.9f}\n")
            P, Q = memoryview(world.positions), memoryview(world.rotations)
            V, W = memoryview(world.velocities), memoryview(world.angular_velocities)
            rows = []
            for i, h in enumerate(handles):
                k = 4 * world.get_index(h)
                rows.append(f"{f},{i},{P[k]:.9g},{P[k+1]:.9g},{P[k+2]:.9g},{Q[k+3]:.9g},{Q[k]:.9g},{Q[k+1]:.9g},{Q[k+2]:.9g},"
                            f"{V[k]:.9g},{V[k+1]:.9g},{V[k+2]:.9g},{W[k]:.9g},{W[k+1]:.9g},{W[k+2]:.9g},"
                            f"{0 if world.is_active(h) else 1}\n")
            out.write("".join(rows))
    print(f"{1e3 * cpu / frames:.4f} {1e3 * wall / frames:.4f}")


def jolt_available():
    if not os.path.exists(JOLT_PYTHON):
        return False
    return subprocess.run([JOLT_PYTHON, "-c", "import culverin"], capture_output=True).returncode == 0


def measure(peer_bench, scene, traj, times, engine):
    """peer_bench's metrics of a trajectory, its ms/step and busy ms/step from
    the per-frame step times (the same summary as `peer_bench run`'s)."""
    r = subprocess.run([peer_bench, "measure", scene, traj, "--engine", engine, "--step-times", times],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"peer_bench measure {engine}: {r.stderr.strip()}")
    return json.loads(r.stdout)


def run_one(a, engine, scene_path, work):
    """The result dict for one engine on one scene, or a string saying why it was skipped."""
    peer_bench = os.path.join(a.build, "tests", "bench", "peer_bench")
    traj = os.path.join(work, f"{engine}.csv")
    times = os.path.join(work, f"{engine}.times")
    try:
        if engine != "jolt":
            name, _, threads = engine.partition(":")  # "fixed:2": the fixed engine on 2 threads
            cmd = [peer_bench, "run", scene_path, "--engine", name, "--frames", str(a.frames)]
            if threads:
                cmd += ["--threads", threads]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                return "skipped: " + (r.stderr.strip().splitlines() or ["peer_bench failed"])[-1]
            res = json.loads(r.stdout)
            if threads and int(threads) > 1:  # CPU time sums the threads: the wall clock is the time a user waits
                res["ms_per_step"], res["busy_ms_per_step"] = res["wall_ms_per_step"], res["busy_wall_ms_per_step"]
                res["wall_clock"] = True
            return res
        else:
            if not jolt_available():
                return "skipped: culverin not found"
            r = subprocess.run([JOLT_PYTHON, os.path.abspath(__file__), "--jolt-worker", scene_path, traj, times,
                                str(a.frames)], capture_output=True, text=True)
            if r.returncode != 0:
                return "skipped: jolt failed: " + r.stderr.strip()[-300:]
            res = measure(peer_bench, scene_path, traj, times, "jolt")
            res["description"] = "Jolt (culverin " + r.stderr.strip() + ", one core)"
            return res
    finally:
        for f in (traj, times):
            if os.path.exists(f):
                os.remove(f)


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--jolt-worker":
        jolt_worker(sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5]))
        return
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--engines", default=",".join(ENGINES))
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--frames", type=int, default=600)
    a = ap.parse_args()
    work = os.path.join(a.build, "peers")
    os.makedirs(work, exist_ok=True)
    lockstep = os.path.join(a.build, "compare", "lockstep")
    print(f"peers.py: {a.frames} frames, engines {a.engines}; ms/step is CPU time per step, busy over frames 31-120",
          flush=True)
    rows = []
    for scene in a.scenes.split(","):
        path = os.path.join(work, f"{scene}.json")
        if scene == "boxfall1000":
            json.dump(boxfall1000(), open(path, "w"))
        else:  # a built-in scene, exported with every field
            with open(path, "w") as f:
                subprocess.run([lockstep, "scenes", scene], stdout=f, check=True)
        for engine in a.engines.split(","):
            t0 = time.time()
            r = run_one(a, engine, path, work)
            took = time.time() - t0
            if isinstance(r, str):
                print(f"{scene} {engine}: {r}", flush=True)
                rows.append(f"| {scene} | {engine} | {r if len(r) <= 90 else r[:87] + '...'} | | | | | |")
                continue
            asleep = str(r["all_asleep_frame"]) if r["all_asleep_frame"] >= 0 else f"never ({r['asleep_at_end']} asleep)"
            print(f"{scene} {engine}: {json.dumps(r)} ({took:.0f} s)", flush=True)
            busy = r.get("busy_ms_per_step")
            busy = "-" if busy is None else f"{busy:.2f}"
            if r.get("wall_clock"):
                engine = f"{engine.split(':')[0]}, {engine.split(':')[1]} threads (wall clock)"
            rows.append(f"| {scene} | {engine} | {r['ms_per_step']:.2f} | {busy} | {asleep} | {r['standing']} / {r['upright']} of {r['columns']} | "
                        f"{r['worst_ground_mm']:.0f} / {r['worst_pair_mm']:.0f} | {r['end_ground_mm']:.1f} / {r['end_pair_mm']:.1f} |")
    print()
    print("| scene | engine | ms/step | busy ms/step (frames 31-120) | all asleep at frame | columns standing / upright | "
          "worst penetration, ground / box-box (mm) | at the end (mm) |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
