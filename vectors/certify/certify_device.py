"""The CUDA device as a certification build (docs/CERTIFICATION.md "The device").

gpu-fixed is the GPU engine's pipeline on Q16.16 (docs/GPU.md "gpu-fixed"). Its
host build is a row of certify.py's matrix (*-gpu-fixed, compiled there like
every other build). Its device build needs nvcc and a GPU, so it is certified
through the `lockstep` command built with CUDA: `lockstep run SCENE --engine
gpu-fixed` on every built-in scene, whose run record (SCENE.csv.run.json)
holds the state hash (eq 92) of every frame 0..N, compared with the vectors'
hashes frame by frame. certify.py adds this row when `nvidia-smi` names a
GPU; a `lockstep` that falls back to its host build (built without CUDA, or
no device) fails the row rather than certifying the host build twice.

  vectors/certify/certify_device.py [--lockstep build/compare/lockstep] [--vectors vectors/data] [--work DIR]

Exit status: 0 every scene's hashes equal the vectors', 1 a scene differs,
2 no device or a run failed.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def device_present():
    """The first GPU as `name, driver` (nvidia-smi), or None."""
    nvsmi = shutil.which("nvidia-smi")
    if nvsmi is None:
        return None
    try:
        p = subprocess.run([nvsmi, "--query-gpu=name,driver_version", "--format=csv,noheader"],
                           capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return None
    lines = p.stdout.strip().splitlines()
    return lines[0].strip() if p.returncode == 0 and lines else None


def run_scene(lockstep, scene, work, timeout):
    """One scene through CUDA: {"hashes": [frame 0..N], "error": None or text}."""
    out = os.path.join(work, "device-%s.csv" % scene)
    cmd = [lockstep, "run", scene, "--engine", "gpu-fixed", "--no-progress", "--every", "1000000", "--out", out]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"hashes": [], "error": "timed out after %d s" % timeout}
    said = p.stdout + p.stderr
    fallback = [l for l in said.splitlines() if "host build" in l or "on the CPU" in l]
    if fallback:
        return {"hashes": [], "error": "ran on the host build, not the device: " + fallback[0].strip()}
    if p.returncode != 0:
        return {"hashes": [], "error": "exit %d: %s" % (p.returncode, said.strip()[-400:])}
    with open(out + ".run.json", encoding="utf-8") as f:
        record = json.load(f)
    return {"hashes": record["hash"], "error": None}


def certify_device(lockstep, ref, scenes, work, timeout=1800):
    """Runs every scene on the device and compares with the vectors (ref: certify.load_vectors).
    Returns {scene: (status, text)}: status "ok", "diff" or "error"."""
    os.makedirs(work, exist_ok=True)
    cells = {}
    for s in scenes:
        got = run_scene(lockstep, s, work, timeout)
        want = ref[s]["hashes"]
        if got["error"]:
            cells[s] = ("error", got["error"])
            continue
        n = min(len(got["hashes"]), len(want))
        bad = next((f for f in range(n) if got["hashes"][f] != want[f]), None)
        if bad is None and len(got["hashes"]) != len(want):
            bad = n
        cells[s] = ("diff", "DIFF@%d" % bad) if bad is not None else ("ok", "all %d" % (len(want) - 1))
    return cells


def main(argv):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import certify  # load_vectors

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lockstep", default=os.path.join(ROOT, "build", "compare", "lockstep"))
    ap.add_argument("--vectors", default=os.path.join(ROOT, "vectors", "data"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build-certify-device"))
    args = ap.parse_args(argv[1:])
    device = device_present()
    if device is None:
        print("certify_device: no CUDA device (nvidia-smi names none)", file=sys.stderr)
        return 2
    if not os.path.exists(args.lockstep):
        print("certify_device: --lockstep %s: not found (build the project with CUDA first)" % args.lockstep,
              file=sys.stderr)
        return 2
    ref = certify.load_vectors(args.vectors)
    cells = certify_device(args.lockstep, ref, list(ref.keys()), args.work)
    print("| build | " + " | ".join(ref.keys()) + " |")
    print("|---|" + "---|" * len(ref))
    print("| `cuda %s gpu-fixed` | %s |" % (device, " | ".join(cells[s][1] for s in ref)))
    if any(c[0] == "error" for c in cells.values()):
        return 2
    return 1 if any(c[0] == "diff" for c in cells.values()) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
