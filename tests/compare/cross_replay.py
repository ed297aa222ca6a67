#!/usr/bin/env python3
"""Cross-build replay (issue 32, docs/RECORDINGS.md "Between builds"): a
recording made by this (x86-64) build's `lockstep run --record` is replayed by
the aarch64 build of the fixed engine under qemu-user and must report no
difference; a recording with one hash changed must be named to its frame.

  cross_replay.py LOCKSTEP SOURCE_DIR WORK_DIR NLOHMANN_INCLUDE

The aarch64 build is the certification's (vectors/certify/certify.py: its
compiler, flags, static link and qemu runner for "aarch64-gcc-O2"), of the
fixed engine's sources, the recording reader and tests/compare/cross/
replay_tool.cpp; it is rebuilt only when a source is newer than it. Exit 0:
passed; 1: failed; 77: skipped (no aarch64 g++ or qemu-aarch64; CI installs
them: .ci/packages). Writes only under WORK_DIR.
"""

import glob
import os
import shutil
import subprocess
import sys
import time


def main(argv):
    lockstep, src, work, nlohmann = argv[1:5]
    sys.path.insert(0, os.path.join(src, "vectors", "certify"))
    import certify  # noqa: E402  (the certification's build matrix: compiler, flags, runner)

    build = certify.Build("aarch64", "gcc", ["-O2"])
    missing = [t for t in build.tools() if shutil.which(t) is None]
    if missing:
        print("SKIP: cross-build replay needs %s (apt-get install g++-aarch64-linux-gnu qemu-user, or bash .ci/packages)"
              % ", ".join(missing))
        return 77
    os.makedirs(work, exist_ok=True)

    # The aarch64 replay tool: the fixed engine (no Boost: world_mp.cpp, and
    # the float and double engines, are left out), the scene loader, the
    # recording reader. nlohmann/json is header-only: only its folder is put
    # on the include path (not the host's /usr/include).
    sources = sorted(glob.glob(os.path.join(src, "fixed", "src", "*.cpp")))
    sources += sorted(f for f in glob.glob(os.path.join(src, "reference", "src", "*.cpp"))
                      if os.path.basename(f) not in ("world_mp.cpp", "world_float.cpp", "world_double.cpp"))
    sources += [os.path.join(src, "compare", "src", "harness", "recording.cpp"),
                os.path.join(src, "tests", "compare", "cross", "replay_tool.cpp")]
    headers = [h for d in ("fixed", "reference", "compare") for h in glob.glob(os.path.join(src, d, "**", "*.hpp"), recursive=True)]
    json_dir = os.path.join(work, "json-include")
    if not os.path.isdir(os.path.join(json_dir, "nlohmann")):
        os.makedirs(json_dir, exist_ok=True)
        os.symlink(os.path.join(nlohmann, "nlohmann"), os.path.join(json_dir, "nlohmann"))
    tool = os.path.join(work, "replay_tool-aarch64")
    newest = max(os.path.getmtime(f) for f in sources + headers + [os.path.abspath(__file__)])
    if not os.path.exists(tool) or os.path.getmtime(tool) < newest:
        t0 = time.time()
        flags = certify.BASE_FLAGS + build.flags + ["-I" + os.path.join(src, d) for d in
                                                    ("fixed/include", "reference/include", "compare/include")]
        flags += ["-I" + json_dir]
        objs, procs = [], []
        for f in sources:  # two compilers at a time
            obj = os.path.join(work, os.path.basename(f) + ".o")
            objs.append(obj)
            procs.append(subprocess.Popen(build.command() + flags + ["-c", f, "-o", obj], stderr=subprocess.PIPE, text=True))
            if len(procs) >= 2:
                p = procs.pop(0)
                if p.wait() != 0:
                    print("FAIL: compiling for aarch64:\n" + p.stderr.read()[-4000:])
                    return 1
        for p in procs:
            if p.wait() != 0:
                print("FAIL: compiling for aarch64:\n" + p.stderr.read()[-4000:])
                return 1
        link = build.command() + objs + ["-o", tool] + (["-static"] if build.arch.static else [])
        r = subprocess.run(link, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            print("FAIL: linking for aarch64:\n" + r.stderr[-4000:])
            return 1
        print("built %s (%s %s, %.0f s)" % (os.path.basename(tool), " ".join(build.command()), " ".join(build.flags),
                                            time.time() - t0))
    runner = build.runner(src)

    failures = []

    def check(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    # A short recording with inputs and snapshots, made by this build.
    inputs = os.path.join(work, "kicks.json")
    with open(inputs, "w") as f:
        f.write('{"format": "lockstep-inputs", "version": 1, "inputs": [\n'
                '  {"frame": 20, "kind": "set_velocity", "id": 4, "velocity": [1.5, 2, 0], "angular_velocity": [0, 3, 0]},\n'
                '  {"frame": 45, "kind": "wake", "id": 0},\n'
                '  {"frame": 50, "kind": "impulse", "id": 2, "impulse": [0.5, 3, 0], "point": [0, 1.2, 0.25]},\n'
                '  {"frame": 70, "kind": "create", "body": {"half_extents": [0.25, 0.5, 0.25], "mass": 0.75, '
                '"position": [0.5, 5, 0], "orientation": [0.9, 0.1, 0.3, 0]}},\n'
                '  {"frame": 80, "kind": "destroy", "id": 1}\n]}\n')
    rec = os.path.join(work, "pyramid.rec.json")
    r = subprocess.run([lockstep, "run", "pyramid", "--frames", "90", "--inputs", inputs, "--record", rec,
                        "--snapshot-every", "30", "--quiet", "--out", os.path.join(work, "pyramid.csv")],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    check(r.returncode == 0 and os.path.exists(rec), "lockstep run --record (x86-64) exits 0 (%r)" % r.stderr[-300:])
    if failures:
        return 1
    t0 = time.time()
    r = subprocess.run(runner + [tool, rec], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    print("  " + r.stdout.strip().replace("\n", "\n  ") + (" (%.1f s under %s)" % (time.time() - t0, runner[0])))
    check(r.returncode == 0 and "replay (aarch64): no difference over 90 frames" in r.stdout,
          "the aarch64 build replays the x86-64 recording: no difference (exit %d, %r)" % (r.returncode, r.stderr[-300:]))

    # One hash changed (frame 60, which has a snapshot): named to its frame.
    text = open(rec).read()
    lines = text.split("\n")
    start = lines.index('  "hashes": [')
    line = lines[start + 60]
    digit = line[5]
    lines[start + 60] = line[:5] + ("0" if digit != "0" else "1") + line[6:]
    bad = os.path.join(work, "pyramid-tampered.rec.json")
    with open(bad, "w") as f:
        f.write("\n".join(lines))
    r = subprocess.run(runner + [tool, bad], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    check(r.returncode == 1 and "differ first at frame 60" in r.stdout,
          "a changed hash is named to its frame (exit %d, %r)" % (r.returncode, r.stdout[-300:]))
    r = subprocess.run(runner + [tool, os.path.join(work, "missing.json")], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    check(r.returncode == 2 and "cannot read" in r.stderr, "a missing recording exits 2 (%r)" % r.stderr[-200:])
    if failures:
        print("%d check(s) failed" % len(failures))
        return 1
    print("cross-build replay: passed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
