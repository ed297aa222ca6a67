#!/usr/bin/env python3
"""Determinism certification of lockstep's fixed engine (docs/CERTIFICATION.md).

Builds the certification driver (vectors/certify/driver.cpp with the fixed
engine's sources only: no Boost, no JSON library) under a matrix of compilers,
optimisation levels and architectures, runs every built-in scene on each build
and proves that every build gives the same state hash (eq 92) after every frame
as the checked-in vectors (vectors/data/scenes/*.json), and the same sleep
frames. Foreign architectures run under qemu-user.

  vectors/certify/certify.py            the full matrix
  vectors/certify/certify.py --ci       the CI subset (2 compilers x 2 optimisation levels + aarch64)
  vectors/certify/certify.py --list     print the matrix and exit
  options: --builds NAME,NAME  --scenes A,B  --jobs N  --work DIR  --vectors DIR  --report FILE  --skip-missing
           --all-frames (no frame limit for emulated -O0 builds; by default they certify pile1000 frames 0-120)

Output: a table of builds by scenes (the frames certified per cell), the
compilers, flags and qemu versions certified. Exit status 0 when every build
agrees with the vectors on every frame; 1 on any difference, naming the first
differing build, scene, frame, body and field; 2 when a build cannot be made
or run (a missing compiler or qemu is an error unless --skip-missing).
Standard library only.
"""

import argparse
import concurrent.futures
import datetime
import fcntl
import hashlib
import json
import os
import platform
import shutil
import subprocess
import sys
import time

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

# The fixed engine's sources (and the driver): exactly what a port of the engine needs.
SOURCES = [
    "fixed/src/q16.cpp",
    "reference/src/run_error.cpp",
    "reference/src/world_fixed.cpp",
    "reference/src/builtin_scenes.cpp",
    "reference/src/sdf_generators.cpp",
    "vectors/certify/driver.cpp",
]
INCLUDES = ["fixed/include", "reference/include"]
# The project's flags for all host code (cmake/LockstepFlags.cmake), before the matrix flags.
BASE_FLAGS = ["-std=c++20", "-ffp-contract=off", "-Wall", "-Wextra", "-Wpedantic", "-Wshadow"]

STATE_FIELDS = ["p.x", "p.y", "p.z", "q.w", "q.x", "q.y", "q.z", "v.x", "v.y", "v.z",
                "w.x", "w.y", "w.z", "asleep", "sleep_counter"]


class Arch:
    def __init__(self, name, gcc, clang_target, runner, static, description):
        self.name = name
        self.gcc = gcc                    # the GNU C++ compiler for this architecture
        self.clang_target = clang_target  # clang++ --target=... (None: native)
        self.runner = runner              # the qemu-user binary, or None (native)
        self.static = static              # link statically (foreign libc is not installed natively)
        self.description = description


ARCHES = {
    "x86_64": Arch("x86_64", "g++", None, None, False, "64-bit x86, native"),
    "i686": Arch("i686", "i686-linux-gnu-g++", "i686-linux-gnu", None, True, "32-bit x86 (x87 FPU by default), native"),
    "aarch64": Arch("aarch64", "aarch64-linux-gnu-g++", "aarch64-linux-gnu", "qemu-aarch64", True,
                    "64-bit ARM, qemu-user"),
    "armhf": Arch("armhf", "arm-linux-gnueabihf-g++", "arm-linux-gnueabihf", "qemu-arm", True,
                  "32-bit ARM (ARMv7, hard float), qemu-user"),
    "s390x": Arch("s390x", "s390x-linux-gnu-g++", "s390x-linux-gnu", "qemu-s390x", True,
                  "64-bit IBM Z, big-endian, qemu-user"),
}


class Build:
    def __init__(self, arch, compiler, flags, limits=None):
        self.arch = ARCHES[arch]
        self.compiler = compiler  # "gcc" or "clang"
        self.flags = flags        # the matrix flags (after BASE_FLAGS)
        self.limits = limits or {}  # scene -> frames certified (default: all)
        self.name = "%s-%s%s" % (arch, compiler, "".join(f.replace("-march=", "-").replace("-f", "-")
                                                         for f in flags).replace(" ", ""))

    def command(self):
        if self.compiler == "gcc":
            cxx = [self.arch.gcc]
        else:
            cxx = ["clang++"] + (["--target=" + self.arch.clang_target] if self.arch.clang_target else [])
        return cxx

    def tools(self):
        t = [self.command()[0]]
        if self.arch.runner:
            t.append(self.arch.runner)
        return t


# Under emulation an -O0 build runs pile1000 for many minutes; by default it
# certifies pile1000's frames 0..EMULATED_O0_PILE_FRAMES only (every other scene,
# and pile1000 on every native and every optimised emulated build, in full).
# --all-frames lifts the limit.
EMULATED_O0_PILE_FRAMES = 120


def matrix_full(all_frames=False):
    b = []
    for cc in ("gcc", "clang"):
        for flags in (["-O0"], ["-O2"], ["-O3"], ["-O3", "-march=native"], ["-O3", "-ffast-math"]):
            b.append(Build("x86_64", cc, flags))
    for flags in (["-O0"], ["-O2"], ["-O3", "-march=native"], ["-O3", "-ffast-math"]):
        b.append(Build("i686", "gcc", flags))
    b.append(Build("i686", "clang", ["-O2"]))
    o0_limits = {} if all_frames else {"pile1000": EMULATED_O0_PILE_FRAMES}
    for arch in ("aarch64", "armhf", "s390x"):
        for flags in (["-O0"], ["-O2"], ["-O3"], ["-O3", "-ffast-math"]):
            b.append(Build(arch, "gcc", flags, o0_limits if flags == ["-O0"] else None))
        b.append(Build(arch, "clang", ["-O2"]))
    return b


def matrix_ci():
    # Two compilers x two optimisation levels, natively, and one foreign
    # architecture (big-endian s390x would do too; aarch64 is the common one).
    return [Build("x86_64", "gcc", ["-O0"]), Build("x86_64", "gcc", ["-O2"]),
            Build("x86_64", "clang", ["-O0"]), Build("x86_64", "clang", ["-O2"]),
            Build("aarch64", "gcc", ["-O2"])]


# ---------------------------------------------------------------------------
# Building and running
# ---------------------------------------------------------------------------

def shown(path):
    """A path relative to the checkout when inside it, else absolute."""
    rel = os.path.relpath(path, ROOT)
    return path if rel.startswith("..") else rel


def run(cmd, timeout=None):
    p = subprocess.run(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def compiler_version(build):
    rc, out, err = run(build.command() + ["--version"])
    return (out or err).splitlines()[0].strip() if rc == 0 else "unavailable"


def snapshot_sources(work):
    """Copies the sources into WORK/src once, so that every build of the matrix
    compiles the same files even if the checkout is edited during the run."""
    dst = os.path.join(work, "src")
    if os.path.exists(dst):
        shutil.rmtree(dst)
    for d in INCLUDES + ["fixed/src", "reference/src"]:
        shutil.copytree(os.path.join(ROOT, d), os.path.join(dst, d))
    os.makedirs(os.path.join(dst, "vectors", "certify"))
    shutil.copy2(os.path.join(ROOT, "vectors", "certify", "driver.cpp"), os.path.join(dst, "vectors", "certify"))
    return dst


def source_fingerprint(src):
    """sha256 over the snapshot's files (path and contents, sorted), and the git
    revision of the checkout with a note when those files differ from it."""
    h = hashlib.sha256()
    for base, _, files in sorted(os.walk(src)):
        for f in sorted(files):
            path = os.path.join(base, f)
            h.update(os.path.relpath(path, src).encode() + b"\0")
            with open(path, "rb") as fh:
                h.update(fh.read())
    rev = "no git"
    rc, out, _ = run(["git", "rev-parse", "--short", "HEAD"])
    if rc == 0:
        rev = out.strip()
        rc, out, _ = run(["git", "status", "--porcelain", "--"] + INCLUDES + ["fixed/src", "reference/src",
                                                                              "vectors/certify/driver.cpp"])
        if rc == 0 and out.strip():
            rev += " + uncommitted changes"
    return h.hexdigest()[:16], rev


def build_and_run(build, work, src, timeout, scenes):
    """Compiles the driver (sources in src) and runs every scene. Returns a result dict."""
    res = {"build": build, "ok": False, "error": None, "output": None, "seconds_build": 0.0, "seconds_run": 0.0}
    exe = os.path.join(work, build.name)
    cmd = (build.command() + BASE_FLAGS + build.flags + ["-I" + os.path.join(src, i) for i in INCLUDES]
           + [os.path.join(src, f) for f in SOURCES] + ["-o", exe])
    if build.arch.static:
        cmd.append("-static")
    res["compile_command"] = " ".join(cmd)
    t0 = time.time()
    try:
        rc, out, err = run(cmd, timeout=timeout)
    except FileNotFoundError as e:
        res["error"] = "compiler not found: %s" % e
        return res
    res["seconds_build"] = time.time() - t0
    if rc != 0:
        res["error"] = "compilation failed:\n" + err[-4000:]
        return res
    runcmd = ([build.arch.runner] if build.arch.runner else []) + [exe] + list(scenes)
    for scene, n in sorted(build.limits.items()):
        runcmd += ["--frames", "%s=%d" % (scene, n)]
    res["run_command"] = runcmd
    t0 = time.time()
    try:
        rc, out, err = run(runcmd, timeout=timeout)
    except FileNotFoundError as e:
        res["error"] = "runner not found: %s" % e
        return res
    except subprocess.TimeoutExpired:
        res["error"] = "run timed out after %d s" % timeout
        return res
    res["seconds_run"] = time.time() - t0
    if rc not in (0, 1):
        res["error"] = "run failed (exit %d):\n%s" % (rc, err[-4000:])
        return res
    res["output"] = parse_driver_output(out)
    res["ok"] = True
    return res


def parse_driver_output(text):
    """driver.cpp's records -> {"build": {...}, "scenes": {name: {...}}}."""
    out = {"build": {}, "scenes": {}}
    cur = None
    for line in text.splitlines():
        f = line.split(" ")
        if f[0] == "build":
            out["build"] = dict(kv.split("=", 1) for kv in f[1:])
        elif f[0] == "scene":
            cur = {"bodies": int(f[3]), "frames": int(f[5]), "hashes": [], "sleep": [], "error": None, "complete": False}
            out["scenes"][f[1]] = cur
        elif f[0] == "h":
            assert int(f[1]) == len(cur["hashes"]), "hash records out of order"
            cur["hashes"].append(f[2])
        elif f[0] == "sleep":
            cur["sleep"].append(int(f[2]))
        elif f[0] == "end":
            cur["complete"] = True
        elif f[0] == "error":
            out["scenes"].setdefault(f[1], cur or {"hashes": [], "sleep": []})["error"] = line
    return out


def dump_state(build, work, scene, frame, timeout):
    exe = os.path.join(work, build.name)
    cmd = ([build.arch.runner] if build.arch.runner else []) + [exe, "--dump", scene, str(frame)]
    rc, out, err = run(cmd, timeout=timeout)
    if rc != 0:
        return None
    rows = []
    for line in out.splitlines():
        f = line.split(" ")
        if f[0] == "state":
            rows.append([int(x) for x in f[3:]])
    return rows


# ---------------------------------------------------------------------------
# The reference: the checked-in vectors
# ---------------------------------------------------------------------------

def load_vectors(directory):
    index_path = os.path.join(directory, "index.json")
    if not os.path.exists(index_path):
        return {}
    with open(index_path, encoding="utf-8") as f:
        index = json.load(f)
    ref = {}
    for entry in index["files"]:
        if entry["level"] != 3:
            continue
        with open(os.path.join(directory, entry["path"]), encoding="utf-8") as f:
            doc = json.load(f)
        ref[doc["scene"]] = {
            "hashes": doc["hashes"],
            "sleep": doc["sleepFrames"],
            "frames": doc["frames"],
            "states": {s["frame"]: s["bodies"] for s in doc["states"]},
            "generator": doc["generatorVersion"],
        }
    return ref


def first_state_difference(want, got):
    for b, (rw, rg) in enumerate(zip(want, got)):
        for k, (x, y) in enumerate(zip(rw, rg)):
            if x != y:
                return b, STATE_FIELDS[k], x, y
    if len(want) != len(got):
        return -1, "body count", len(want), len(got)
    return None


def compare(result, ref, scenes):
    """Fills result["cells"][scene] = (status, text, first differing frame or None)."""
    cells = {}
    out = result["output"]
    for s in scenes:
        got = out["scenes"].get(s)
        want = ref.get(s)
        if got is None:
            cells[s] = ("error", "not run", None)
            continue
        if got.get("error"):
            cells[s] = ("diff", "stopped", len(got["hashes"]))
            continue
        if want is None:
            cells[s] = ("noref", "%d (no vectors)" % (len(got["hashes"]) - 1), None)
            continue
        n = len(got["hashes"])
        bad = next((f for f in range(min(n, len(want["hashes"]))) if got["hashes"][f] != want["hashes"][f]), None)
        if bad is None and n > len(want["hashes"]):
            bad = len(want["hashes"])
        if bad is not None:
            cells[s] = ("diff", "DIFF@%d" % bad, bad)
            continue
        full = n == want["frames"] + 1
        if full and got["sleep"] != want["sleep"]:
            body = next(i for i, (a, b) in enumerate(zip(want["sleep"], got["sleep"])) if a != b)
            cells[s] = ("diff", "SLEEP", None)
            result.setdefault("sleep_diffs", {})[s] = (body, want["sleep"][body], got["sleep"][body])
            continue
        cells[s] = ("ok", "all %d" % (n - 1) if full else "0-%d of %d" % (n - 1, want["frames"]), None)
    result["cells"] = cells


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------

def markdown_table(results, scenes):
    head = "| build | " + " | ".join(scenes) + " |"
    sep = "|---|" + "---|" * len(scenes)
    rows = [head, sep]
    for r in results:
        b = r["build"]
        label = "`%s %s %s`" % (b.arch.name, b.compiler, " ".join(b.flags))
        if not r["ok"]:
            rows.append("| %s | %s |" % (label, " | ".join(["BUILD/RUN ERROR"] + [""] * (len(scenes) - 1))))
            continue
        rows.append("| %s | %s |" % (label, " | ".join(r["cells"][s][1] for s in scenes)))
    return "\n".join(rows)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ci", action="store_true", help="the CI subset")
    ap.add_argument("--list", action="store_true", help="print the matrix and exit")
    ap.add_argument("--builds", default="", help="comma-separated build names (see --list) to run only those")
    ap.add_argument("--scenes", default="", help="comma-separated scenes to certify (default: every built-in scene)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--work", default=os.path.join(ROOT, "build-certify"), help="where the binaries go")
    ap.add_argument("--vectors", default=os.path.join(ROOT, "vectors", "data"))
    ap.add_argument("--report", default="", help="also write the report (Markdown) to this file")
    ap.add_argument("--timeout", type=int, default=1800, help="seconds per compile or run")
    ap.add_argument("--skip-missing", action="store_true", help="skip builds whose compiler or qemu is not installed")
    ap.add_argument("--all-frames", action="store_true",
                    help="certify every frame on every build (no limit for emulated -O0 builds)")
    args = ap.parse_args(argv[1:])

    full = matrix_full(args.all_frames)
    builds = matrix_ci() if args.ci else full
    if args.builds:
        wanted = args.builds.split(",")
        pool = {b.name: b for b in matrix_ci() + full}
        unknown = [w for w in wanted if w not in pool]
        if unknown:
            print("certify: unknown build(s) %s; see --list" % ", ".join(unknown), file=sys.stderr)
            return 2
        builds = [pool[w] for w in wanted]
    if args.list:
        for b in builds:
            limits = ", ".join("%s frames 0-%d" % kv for kv in sorted(b.limits.items()))
            print("%-28s %-9s %-6s %-22s %s%s" % (b.name, b.arch.name, b.compiler, " ".join(b.flags), b.arch.description,
                                                 "; " + limits if limits else ""))
        sys.stdout.flush()
        return 0

    missing = sorted({t for b in builds for t in b.tools() if shutil.which(t) is None})
    if missing:
        if not args.skip_missing:
            print("certify: not installed: %s (Debian: see docs/CERTIFICATION.md; or --skip-missing)" % ", ".join(missing),
                  file=sys.stderr)
            return 2
        builds = [b for b in builds if not any(t in missing for t in b.tools())]
        print("certify: skipping builds that need %s" % ", ".join(missing))

    os.makedirs(args.work, exist_ok=True)
    # One run per work directory: a second one would overwrite the first's binaries.
    lock = open(os.path.join(args.work, ".lock"), "w")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        print("certify: another certification is running in %s (use --work DIR)" % args.work, file=sys.stderr)
        return 2
    src = snapshot_sources(args.work)
    fingerprint, revision = source_fingerprint(src)
    ref = load_vectors(args.vectors)
    if not ref:
        print("certify: no scene vectors in %s (run: lockstep vectors generate vectors/data)" % args.vectors,
              file=sys.stderr)
        return 2

    selected = [x for x in args.scenes.split(",") if x]
    unknown = [x for x in selected if x not in ref]
    if unknown:
        print("certify: no vectors for scene(s) %s in %s" % (", ".join(unknown), args.vectors), file=sys.stderr)
        return 2

    start = time.time()
    print("certify: %d builds, %d jobs, reference %s" % (len(builds), args.jobs, shown(args.vectors)),
          flush=True)
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as ex:
        futures = {ex.submit(build_and_run, b, args.work, src, args.timeout, selected): b for b in builds}
        for fut in concurrent.futures.as_completed(futures):
            r = fut.result()
            print("  %-28s %s (build %.0f s, run %.0f s)" % (r["build"].name, "done" if r["ok"] else "FAILED",
                                                             r["seconds_build"], r["seconds_run"]), flush=True)
            results.append(r)
    order = {b.name: i for i, b in enumerate(builds)}
    results.sort(key=lambda r: order[r["build"].name])

    scenes = selected or list(ref.keys())
    for r in results:
        if r["ok"] and not selected:
            for s in r["output"]["scenes"]:
                if s not in scenes:
                    scenes.append(s)
    for r in results:
        if r["ok"]:
            compare(r, ref, scenes)

    # The first difference, located to body and field.
    first = None
    for r in results:
        if not r["ok"]:
            continue
        for s in scenes:
            st, text, frame = r["cells"][s]
            if st == "diff" and first is None:
                first = (r, s, frame, text)
    detail = []
    if first is not None:
        r, s, frame, text = first
        b = r["build"]
        if frame is not None and text.startswith("DIFF"):
            got = dump_state(b, args.work, s, frame, args.timeout)
            want = ref[s]["states"].get(frame)
            source = "the vectors' stored state"
            if want is None:
                base = next((x for x in results if x["ok"] and x["cells"][s][0] == "ok" and not x["build"].arch.runner),
                            None)
                if base is not None:
                    want = dump_state(base["build"], args.work, s, frame, args.timeout)
                    source = "build %s (which agrees with the vectors)" % base["build"].name
            d = first_state_difference(want, got) if (want is not None and got is not None) else None
            if d is not None:
                detail.append("first difference: build %s, scene %s, frame %d, body %d, field %s: expected %s (%s), "
                              "got %s" % (b.name, s, frame, d[0], d[1], d[2], source, d[3]))
            else:
                detail.append("first difference: build %s, scene %s, frame %d: state hash expected %s, got %s"
                              % (b.name, s, frame, ref[s]["hashes"][frame], r["output"]["scenes"][s]["hashes"][frame]))
        elif text == "SLEEP":
            body, w, g = r["sleep_diffs"][s]
            detail.append("first difference: build %s, scene %s, body %d, sleep frame: expected %d, got %d"
                          % (b.name, s, body, w, g))
        else:
            detail.append("first difference: build %s, scene %s: %s" % (b.name, s, r["output"]["scenes"][s].get("error")))

    failures = [r for r in results if not r["ok"]]
    diffs = [r for r in results if r["ok"] and any(c[0] == "diff" for c in r["cells"].values())]

    lines = []
    lines.append("## Certification run %s" % datetime.date.today().isoformat())
    lines.append("")
    cpu = ""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), "")
    except OSError:
        pass
    lines.append("Machine: %s %s, %s; Python %s. Reference: `%s` (%s)." % (
        platform.system(), platform.machine(), cpu or "unknown CPU", platform.python_version(),
        shown(args.vectors), next(iter(ref.values()))["generator"]))
    lines.append("")
    lines.append("Engine sources certified: git %s; sha256 of the %s files: `%s`." % (
        revision, "fixed/, reference/include, reference/src and driver", fingerprint))
    lines.append("")
    lines.append("Base flags of every build: `%s` (the project's), then the matrix flags; cross and i686 builds "
                 "are linked `-static`. Cells: the frames whose state hash (eq 92) equals the vectors' "
                 "(`all N`: frames 0..N, every frame of the scene, plus every body's sleep frame; `0-K of N`: frames "
                 "0..K only); `DIFF@f`: the first differing frame." % " ".join(BASE_FLAGS))
    lines.append("")
    lines.append(markdown_table(results, scenes))
    lines.append("")
    lines.append("| build | compiler | binary reports | build s | run s |")
    lines.append("|---|---|---|---|---|")
    versions = {}
    for r in results:
        b = r["build"]
        key = tuple(b.command())
        if key not in versions:
            versions[key] = compiler_version(b)
        info = r["output"]["build"] if r["ok"] else {}
        rep = "%s-bit %s-endian, %s%s" % (info.get("pointer_bits", "?"), info.get("endian", "?"),
                                          info.get("compiler", "?"),
                                          ", fast-math" if info.get("fast_math") == "yes" else "")
        lines.append("| `%s` | %s%s | %s | %.0f | %.0f |" % (
            b.name, versions[key], (" under " + b.arch.runner) if b.arch.runner else "", rep,
            r["seconds_build"], r["seconds_run"]))
    runners = sorted({b.arch.runner for b in builds if b.arch.runner})
    for q in runners:
        rc, out, _ = run([q, "--version"])
        lines.append("")
        lines.append("%s: %s" % (q, out.splitlines()[0] if rc == 0 and out else "unavailable"))
    lines.append("")
    total = time.time() - start
    if failures or diffs:
        lines.append("**FAILED**: %d build(s) could not be made or run, %d build(s) differ." % (len(failures), len(diffs)))
        for r in failures:
            lines.append("- %s: %s" % (r["build"].name, r["error"]))
        lines.extend("- " + d for d in detail)
    else:
        lines.append("**CERTIFIED**: %d builds x %d scenes agree with the vectors on every certified frame (%.0f s)."
                     % (len(results), len(scenes), total))
    report = "\n".join(lines)
    print()
    print(report)
    if args.report:
        with open(args.report, "w", encoding="utf-8") as f:
            f.write(report + "\n")
    if failures:
        return 2
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
