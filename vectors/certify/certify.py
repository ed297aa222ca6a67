#!/usr/bin/env python3
"""Determinism certification of lockstep's fixed engine (docs/CERTIFICATION.md).

Builds the certification driver (vectors/certify/driver.cpp with the fixed
engine's sources only: no Boost, no JSON library; the rows *-gpu-fixed with
the GPU engine's pipeline on Q16.16 instead, host build, docs/GPU.md
"gpu-fixed") under a matrix of compilers,
optimisation levels and architectures, runs every built-in scene on each build
and proves that every build gives the same state hash (eq 92) after every frame
as the checked-in vectors (vectors/data/scenes/*.json), and the same sleep
frames. Foreign Linux architectures run under qemu-user; WebAssembly
(emscripten, and clang's wasm32-wasi) under Node.js; 64-bit Windows (mingw-w64)
under wine.

  vectors/certify/certify.py            the full matrix
  vectors/certify/certify.py --ci       the CI subset (2 compilers x 2 optimisation levels + aarch64 + gpu-fixed)
  vectors/certify/certify.py --list     print the matrix and exit
  options: --builds NAME,NAME  --scenes A,B  --jobs N  --work DIR  --vectors DIR  --report FILE  --skip-missing
           --all-frames (no frame limit for emulated -O0 builds; by default they certify pile1000 frames 0-120)

Output: a table of builds by scenes (the frames certified per cell), the
compilers, flags and qemu/node/wine versions certified. Exit status 0 when
every build agrees with the vectors on every frame; 1 on any difference, naming
the first differing build, scene, frame, body and field; 2 when a build cannot
be made or run (a missing compiler or qemu is an error unless --skip-missing;
the full matrix's WebAssembly and Windows builds are skipped, each named, where
emscripten, the wasi sysroot, node, mingw-w64 or wine is missing).
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
import threading
import time

import certify_device  # the CUDA device row (gpu-fixed through CUDA)

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

# The fixed engine's sources (and the driver): exactly what a port of the engine needs.
SOURCES = [
    "fixed/src/q16.cpp",
    "reference/src/run_error.cpp",
    "reference/src/world_fixed.cpp",
    "reference/src/thread_pool.cpp",
    "reference/src/snapshot_scene.cpp",
    "reference/src/builtin_scenes.cpp",
    "reference/src/sdf_generators.cpp",
    "vectors/certify/driver.cpp",
]
INCLUDES = ["fixed/include", "reference/include"]
# gpu-fixed builds (docs/GPU.md "gpu-fixed"): the same driver on the GPU
# engine's pipeline on Q16.16, host build (driver.cpp with
# -DLOCKSTEP_CERTIFY_GPU_FIXED, vectors/certify/gpu_fixed_engine.hpp), which
# must give the same vectors on every built-in scene, every frame.
GPU_FIXED_SOURCES = ["gpu/src/host.cpp", "gpu/src/initial_state.cpp"]
GPU_FIXED_INCLUDES = ["gpu/include", "gpu/src", "compare/include", "vectors/certify"]
GPU_FIXED_DEFINES = ["-DLOCKSTEP_CERTIFY_GPU_FIXED"]
# The driver and the platform files some builds add (wasm32-wasi's throw, its Node.js runner).
CERTIFY_FILES = ["vectors/certify/driver.cpp", "vectors/certify/gpu_fixed_engine.hpp", "vectors/certify/wasi_throw.cpp",
                 "vectors/certify/run_wasi.mjs"]
# The project's flags for all host code (cmake/LockstepFlags.cmake), before the matrix flags.
BASE_FLAGS = ["-std=c++20", "-ffp-contract=off", "-Wall", "-Wextra", "-Wpedantic", "-Wshadow"]

STATE_FIELDS = ["p.x", "p.y", "p.z", "q.w", "q.x", "q.y", "q.z", "v.x", "v.y", "v.z",
                "w.x", "w.y", "w.z", "asleep", "sleep_counter"]


class Arch:
    def __init__(self, name, gcc, clang_target, runner, static, description, compilers=None, exe_suffix="",
                 link_flags=(), extra_sources=(), env=None, probes=(), setup=None, optional=False):
        self.name = name
        self.gcc = gcc                    # the GNU C++ compiler for this architecture
        self.clang_target = clang_target  # clang++ --target=... (None: native)
        self.runner = list(runner or [])  # the command line that runs a binary (qemu-user, node, wine); [] = native
        self.static = static              # link statically (foreign libc is not installed natively)
        self.description = description
        self.compilers = compilers or {}  # other compilers: name -> command (e.g. "emscripten": ["em++"])
        self.exe_suffix = exe_suffix      # the binary's name ends so (".js", ".wasm", ".exe")
        self.link_flags = list(link_flags)        # after the sources, for this platform only
        self.extra_sources = list(extra_sources)  # vectors/certify/ files this platform links in too
        self.env = env                    # work -> extra environment of compile and run, or None
        self.probes = list(probes)        # (what is missing, Debian package, check(command) -> bool)
        self.setup = setup                # (work, env) -> (note, seconds): once per run before its first run
        self.optional = optional          # beyond Linux: skipped, with a message, where its tools are missing

    def runner_name(self):
        return os.path.basename(self.runner[0]) if self.runner else ""


# emscripten (Debian's 3.1.6) runs its JavaScript optimiser (acorn) under node;
# Debian installs acorn in /usr/share/nodejs, which a node not from Debian
# (e.g. NodeSource's) does not search.
def emscripten_env(work):
    return {"NODE_PATH": os.pathsep.join(x for x in (os.environ.get("NODE_PATH", ""), "/usr/share/nodejs") if x)}


# wine keeps its Windows (C: drive, registry) in a prefix: one per work
# directory, created by the first run; no debug chatter; no Mono or Gecko
# installer dialogs while it is created.
def wine_env(work):
    return {"WINEPREFIX": os.path.join(os.path.abspath(work), "wineprefix"), "WINEDEBUG": "-all",
            "WINEDLLOVERRIDES": "mscoree,mshtml="}


def wine_setup(work, env):
    """Creates the wine prefix (a first wine start takes seconds to a minute);
    the time counts in the run time of the build that waited for it."""
    prefix = env["WINEPREFIX"]
    if os.path.exists(os.path.join(prefix, "system.reg")):
        return None
    t0 = time.time()
    p = subprocess.run(["wine", "wineboot", "--init"], cwd=ROOT, env=dict(os.environ, **env), stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=600)
    if p.returncode != 0 or not os.path.exists(os.path.join(prefix, "system.reg")):
        raise RuntimeError("wine could not create its prefix %s (exit %d):\n%s" % (prefix, p.returncode,
                                                                                   p.stderr[-2000:]))
    return "wine prefix %s created" % shown(prefix), time.time() - t0


def wasi_sysroot_installed(cxx):
    """clang finds the wasm32-wasi C and C++ libraries and its builtins."""
    for arg in ("-print-file-name=libc.a", "-print-file-name=libc++.a", "-print-libgcc-file-name"):
        try:
            p = subprocess.run(cxx + [arg], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, timeout=60)
        except OSError:
            return False
        path = p.stdout.strip()
        if p.returncode != 0 or not os.path.isabs(path) or not os.path.exists(path):
            return False
    return True


ARCHES = {
    "x86_64": Arch("x86_64", "g++", None, None, False, "64-bit x86, native"),
    "i686": Arch("i686", "i686-linux-gnu-g++", "i686-linux-gnu", None, True, "32-bit x86 (x87 FPU by default), native"),
    "aarch64": Arch("aarch64", "aarch64-linux-gnu-g++", "aarch64-linux-gnu", ["qemu-aarch64"], True,
                    "64-bit ARM, qemu-user"),
    "armhf": Arch("armhf", "arm-linux-gnueabihf-g++", "arm-linux-gnueabihf", ["qemu-arm"], True,
                  "32-bit ARM (ARMv7, hard float), qemu-user"),
    "s390x": Arch("s390x", "s390x-linux-gnu-g++", "s390x-linux-gnu", ["qemu-s390x"], True,
                  "64-bit IBM Z, big-endian, qemu-user"),
    # The browser's WebAssembly: emscripten's JavaScript + wasm under Node.js
    # (V8, the engine of Chrome). Node >= 18 has a global fetch(), with which
    # emscripten 3.1.6's asynchronous loader tries to fetch the .wasm by its
    # file path and fails; the synchronous loader reads the file. The heap may grow.
    "wasm32": Arch("wasm32", None, None, ["node"], False, "WebAssembly, emscripten, under Node.js",
                   compilers={"emscripten": ["em++"]}, exe_suffix=".js",
                   link_flags=["-sENVIRONMENT=node", "-sWASM_ASYNC_COMPILATION=0", "-sALLOW_MEMORY_GROWTH=1"],
                   env=emscripten_env, optional=True),
    # WASI: clang's wasm32-wasi with wasi-libc and libc++ for wasm32, under
    # Node.js's WASI. That libc++abi has no exceptions; wasi_throw.cpp ends the
    # run on a throw (no built-in scene throws).
    "wasm32-wasi": Arch("wasm32-wasi", None, "wasm32-wasi",
                        ["node", "--no-warnings", os.path.join("{src}", "vectors", "certify", "run_wasi.mjs")], False,
                        "WebAssembly, WASI preview 1, under Node.js's WASI", exe_suffix=".wasm",
                        extra_sources=["vectors/certify/wasi_throw.cpp"],
                        probes=[("the wasm32-wasi sysroot",
                                 "wasi-libc libc++-14-dev-wasm32 libc++abi-14-dev-wasm32 libclang-rt-14-dev-wasm32",
                                 wasi_sysroot_installed)],
                        optional=True),
    # 64-bit Windows: mingw-w64's g++ (msvcrt, the win32 thread model), under wine.
    "win64": Arch("win64", "x86_64-w64-mingw32-g++", None, ["wine"], True, "64-bit Windows (mingw-w64), under wine",
                  exe_suffix=".exe", env=wine_env, setup=wine_setup, optional=True),
}


class Build:
    def __init__(self, arch, compiler, flags, limits=None, engine="fixed"):
        self.arch = ARCHES[arch]
        self.compiler = compiler  # "gcc", "clang" or one of the architecture's compilers ("emscripten")
        self.flags = flags        # the matrix flags (after BASE_FLAGS)
        self.limits = limits or {}  # scene -> frames certified (default: all)
        self.engine = engine      # "fixed" (World<Q16>) or "gpu-fixed" (the GPU engine's pipeline, host build)
        self.name = "%s-%s%s%s" % (arch, compiler, "".join(f.replace("-march=", "-").replace("-f", "-")
                                                           for f in flags).replace(" ", ""),
                                   "-gpu-fixed" if engine == "gpu-fixed" else "")

    def sources(self):
        return SOURCES + (GPU_FIXED_SOURCES if self.engine == "gpu-fixed" else [])

    def includes(self):
        return INCLUDES + (GPU_FIXED_INCLUDES if self.engine == "gpu-fixed" else [])

    def defines(self):
        return GPU_FIXED_DEFINES if self.engine == "gpu-fixed" else []

    def command(self):
        if self.compiler in self.arch.compilers:
            return list(self.arch.compilers[self.compiler])
        if self.compiler == "gcc":
            return [self.arch.gcc]
        return ["clang++"] + (["--target=" + self.arch.clang_target] if self.arch.clang_target else [])

    def tools(self):
        t = [self.command()[0]]
        if self.arch.runner:
            t.append(self.arch.runner[0])
        return t

    def env(self, work):
        return self.arch.env(work) if self.arch.env else {}

    def executable(self, work):
        return os.path.join(work, self.name + self.arch.exe_suffix)

    def runner(self, src):
        return [a.replace("{src}", src) for a in self.arch.runner]


def debian_packages(missing_lists):
    """The Debian packages that provide the missing tools, for a message."""
    pk = []
    for m in missing_lists:
        for what, package in m:
            for p in (package or PACKAGES.get(what, what)).split():
                if p not in pk:
                    pk.append(p)
    return " ".join(pk)


def missing_tools(build, cache):
    """What this build needs and this machine lacks: commands not on PATH, then
    failed probes (a sysroot), as [(what, Debian package or None)]."""
    missing = [(t, None) for t in build.tools() if shutil.which(t) is None]
    if not missing:
        for what, package, check in build.arch.probes:
            key = (what, tuple(build.command()))
            if key not in cache:
                cache[key] = check(build.command())
            if not cache[key]:
                missing.append((what, package))
    return missing


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
    # Beyond Linux: the browser's WebAssembly, WASI and Windows.
    for flags in (["-O2"], ["-O3"]):
        b.append(Build("wasm32", "emscripten", flags))
    for flags in (["-O2"], ["-O3"]):
        b.append(Build("wasm32-wasi", "clang", flags))
    for flags in (["-O2"], ["-O3", "-ffast-math"]):
        b.append(Build("win64", "gcc", flags))
    # gpu-fixed: the GPU engine's pipeline on Q16.16 (host build), natively and on aarch64.
    for cc, flags in (("gcc", ["-O2"]), ("clang", ["-O2"]), ("gcc", ["-O3", "-ffast-math"])):
        b.append(Build("x86_64", cc, flags, engine="gpu-fixed"))
    b.append(Build("aarch64", "gcc", ["-O2"], engine="gpu-fixed"))
    return b


def matrix_ci():
    # Two compilers x two optimisation levels, natively, and one foreign
    # architecture (big-endian s390x would do too; aarch64 is the common one).
    return [Build("x86_64", "gcc", ["-O0"]), Build("x86_64", "gcc", ["-O2"]),
            Build("x86_64", "clang", ["-O0"]), Build("x86_64", "clang", ["-O2"]),
            Build("aarch64", "gcc", ["-O2"]), Build("x86_64", "gcc", ["-O2"], engine="gpu-fixed")]


# The Debian (bookworm) packages that provide each tool, for the messages.
PACKAGES = {
    "g++": "g++", "clang++": "clang", "i686-linux-gnu-g++": "g++-i686-linux-gnu",
    "aarch64-linux-gnu-g++": "g++-aarch64-linux-gnu", "arm-linux-gnueabihf-g++": "g++-arm-linux-gnueabihf",
    "s390x-linux-gnu-g++": "g++-s390x-linux-gnu", "qemu-aarch64": "qemu-user", "qemu-arm": "qemu-user",
    "qemu-s390x": "qemu-user", "em++": "emscripten", "node": "nodejs", "wine": "wine wine64",
    "x86_64-w64-mingw32-g++": "g++-mingw-w64-x86-64",
}


# ---------------------------------------------------------------------------
# Building and running
# ---------------------------------------------------------------------------

def shown(path):
    """A path relative to the checkout when inside it, else absolute."""
    rel = os.path.relpath(path, ROOT)
    return path if rel.startswith("..") else rel


def run(cmd, timeout=None, env=None):
    p = subprocess.run(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout,
                       env=dict(os.environ, **env) if env else None)
    return p.returncode, p.stdout, p.stderr


def compiler_version(build):
    try:
        rc, out, err = run(build.command() + ["--version"])
    except OSError:
        return "unavailable"
    return (out or err).splitlines()[0].strip() if rc == 0 and (out or err) else "unavailable"


def snapshot_sources(work):
    """Copies the sources into WORK/src once, so that every build of the matrix
    compiles the same files even if the checkout is edited during the run."""
    dst = os.path.join(work, "src")
    if os.path.exists(dst):
        shutil.rmtree(dst)
    for d in INCLUDES + ["fixed/src", "reference/src", "gpu/include", "gpu/src", "compare/include"]:
        shutil.copytree(os.path.join(ROOT, d), os.path.join(dst, d))
    os.makedirs(os.path.join(dst, "vectors", "certify"))
    for f in CERTIFY_FILES:
        shutil.copy2(os.path.join(ROOT, f), os.path.join(dst, "vectors", "certify"))
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
        rc, out, _ = run(["git", "status", "--porcelain", "--"] + INCLUDES + ["fixed/src", "reference/src"]
                         + GPU_FIXED_INCLUDES[:3] + GPU_FIXED_SOURCES
                         + CERTIFY_FILES)
        if rc == 0 and out.strip():
            rev += " + uncommitted changes"
    return h.hexdigest()[:16], rev


_SETUP_LOCK = threading.Lock()
_SETUP_DONE = {}  # (architecture, work directory) -> None when done, or the exception it raised


def platform_setup(build, work, env):
    """Runs the architecture's one-time setup (the wine prefix) once per work
    directory; later builds wait for it. Returns (note, seconds) for the build
    that ran it, else None."""
    if build.arch.setup is None:
        return None
    key = (build.arch.name, os.path.abspath(work))
    with _SETUP_LOCK:
        if key in _SETUP_DONE:
            if _SETUP_DONE[key] is not None:
                raise _SETUP_DONE[key]
            return None
        try:
            r = build.arch.setup(work, env)
        except (OSError, RuntimeError, subprocess.TimeoutExpired) as e:
            _SETUP_DONE[key] = RuntimeError(str(e))
            raise
        _SETUP_DONE[key] = None
        return r


def build_and_run(build, work, src, timeout, scenes):
    """Compiles the driver (sources in src) and runs every scene. Returns a result dict."""
    res = {"build": build, "ok": False, "error": None, "output": None, "seconds_build": 0.0, "seconds_run": 0.0,
           "setup": None}
    exe = build.executable(work)
    env = build.env(work)
    cmd = (build.command() + BASE_FLAGS + build.flags + build.defines() + ["-I" + os.path.join(src, i) for i in build.includes()]
           + [os.path.join(src, f) for f in build.sources() + build.arch.extra_sources] + build.arch.link_flags
           + ["-o", exe])
    if build.arch.static:
        cmd.append("-static")
    res["compile_command"] = " ".join(cmd)
    t0 = time.time()
    try:
        rc, out, err = run(cmd, timeout=timeout, env=env)
    except FileNotFoundError as e:
        res["error"] = "compiler not found: %s" % e
        return res
    res["seconds_build"] = time.time() - t0
    if rc != 0:
        res["error"] = "compilation failed:\n" + err[-4000:]
        return res
    runcmd = build.runner(src) + [exe] + list(scenes)
    for scene, n in sorted(build.limits.items()):
        runcmd += ["--frames", "%s=%d" % (scene, n)]
    res["run_command"] = runcmd
    t0 = time.time()
    try:
        res["setup"] = platform_setup(build, work, env)
    except (OSError, RuntimeError, subprocess.TimeoutExpired) as e:
        res["error"] = "setup of %s failed: %s" % (build.arch.name, e)
        return res
    try:
        rc, out, err = run(runcmd, timeout=timeout, env=env)
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
    try:
        res["output"] = parse_driver_output(out)
    except (ValueError, IndexError, TypeError) as e:  # a garbled record: the build fails, naming the line; the matrix goes on
        res["error"] = "unreadable output: %s" % e
        return res
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
            if cur is None or len(f) < 3 or not f[1].isdigit() or int(f[1]) != len(cur["hashes"]):
                raise ValueError("hash record out of order or malformed: %r" % line[:200])
            cur["hashes"].append(f[2])
        elif f[0] == "sleep":
            cur["sleep"].append(int(f[2]))
        elif f[0] == "end":
            cur["complete"] = True
        elif f[0] == "error":
            out["scenes"].setdefault(f[1], cur or {"hashes": [], "sleep": []})["error"] = line
    return out


def dump_state(build, work, src, scene, frame, timeout):
    cmd = build.runner(src) + [build.executable(work), "--dump", scene, str(frame)]
    rc, out, err = run(cmd, timeout=timeout, env=build.env(work))
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
        label = "`%s %s %s%s`" % (b.arch.name, b.compiler, " ".join(b.flags),
                                  " gpu-fixed" if b.engine == "gpu-fixed" else "")
        if r.get("skipped"):
            rows.append("| %s | %s |" % (label, " | ".join(["SKIPPED: " + r["skipped"]] + [""] * (len(scenes) - 1))))
            continue
        if not r["ok"]:
            rows.append("| %s | %s |" % (label, " | ".join(["BUILD/RUN ERROR"] + [""] * (len(scenes) - 1))))
            continue
        rows.append("| %s | %s |" % (label, " | ".join(r["cells"][s][1] for s in scenes)))
    return "\n".join(rows)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ci", action="store_true", help="the CI subset")
    ap.add_argument("--device-lockstep", default=os.path.join(ROOT, "build", "compare", "lockstep"),
                    help="with a CUDA device present (nvidia-smi): the lockstep built with CUDA whose gpu-fixed "
                         "runs certify the device (certify_device.py)")
    ap.add_argument("--no-device", action="store_true", help="leave the CUDA device out even when present")
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
            print("%-28s %-11s %-10s %-22s %s%s" % (b.name, b.arch.name, b.compiler, " ".join(b.flags),
                                                   b.arch.description, "; " + limits if limits else ""))
        sys.stdout.flush()
        return 0

    # A missing tool is an error (exit 2), unless --skip-missing; the matrix's
    # builds beyond Linux (WebAssembly, Windows) are skipped where their tools
    # are missing. Every skipped build is named here and in the report.
    probe_cache = {}
    requested = list(builds)
    missing = [(b, m) for b, m in ((b, missing_tools(b, probe_cache)) for b in builds) if m]
    skipped = []
    if missing:
        hard = [(b, m) for b, m in missing if not (b.arch.optional and not args.builds)]
        if hard and not args.skip_missing:
            what = sorted({w for _, m in hard for w, _ in m})
            print("certify: not installed: %s, needed by %s (Debian: apt-get install %s; see docs/CERTIFICATION.md; "
                  "or --skip-missing)" % (", ".join(what), ", ".join(b.name for b, _ in hard),
                                          debian_packages(m for _, m in hard)), file=sys.stderr)
            return 2
        for b, m in missing:
            print("certify: SKIPPED %s: not installed: %s (Debian: apt-get install %s)"
                  % (b.name, ", ".join(w for w, _ in m), debian_packages([m])), flush=True)
            skipped.append({"build": b, "ok": False, "skipped": "not installed: " + ", ".join(w for w, _ in m)})
        builds = [b for b in builds if all(b is not x["build"] for x in skipped)]

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
    order_all = {b.name: i for i, b in enumerate(requested)}
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

    # The CUDA device (certify_device.py): gpu-fixed through CUDA, when a GPU is present.
    device = None if args.no_device else certify_device.device_present()
    device_cells = None
    if device is not None:
        print("certify: the CUDA device (%s): gpu-fixed through %s" % (device, shown(args.device_lockstep)), flush=True)
        device_cells = certify_device.certify_device(args.device_lockstep, ref, scenes,
                                                     os.path.join(args.work, "device"), args.timeout)

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
            got = dump_state(b, args.work, src, s, frame, args.timeout)
            want = ref[s]["states"].get(frame)
            source = "the vectors' stored state"
            if want is None:
                base = next((x for x in results if x["ok"] and x["cells"][s][0] == "ok" and not x["build"].arch.runner),
                            None)
                if base is not None:
                    want = dump_state(base["build"], args.work, src, s, frame, args.timeout)
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
        revision, "fixed/, reference/include, reference/src and vectors/certify (driver, wasi files)", fingerprint))
    lines.append("")
    lines.append("Base flags of every build: `%s` (the project's), then the matrix flags; cross, i686 and win64 "
                 "builds are linked `-static`; emscripten's add `%s`. Cells: the frames whose state hash (eq 92) equals the vectors' "
                 "(`all N`: frames 0..N, every frame of the scene, plus every body's sleep frame; `0-K of N`: frames "
                 "0..K only); `DIFF@f`: the first differing frame; `SKIPPED`: its tools are not installed."
                 % (" ".join(BASE_FLAGS), " ".join(ARCHES["wasm32"].link_flags)))
    lines.append("")
    lines.append(markdown_table(sorted(results + skipped, key=lambda r: order_all[r["build"].name]), scenes))
    if device_cells is not None:
        lines.append("| `cuda %s gpu-fixed` (the device, every frame's hash) | %s |"
                     % (device, " | ".join(device_cells[s][1] for s in scenes)))
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
            b.name, versions[key], (" under " + b.arch.runner_name()) if b.arch.runner else "", rep,
            r["seconds_build"], r["seconds_run"]))
    runners = sorted({b.arch.runner[0] for b in builds if b.arch.runner})
    for q in runners:
        try:
            rc, out, _ = run([q, "--version"])
        except OSError:
            rc, out = 1, ""
        lines.append("")
        lines.append("%s: %s" % (q, out.splitlines()[0] if rc == 0 and out else "unavailable"))
    for r in results:
        if r.get("setup"):
            lines.append("")
            lines.append("%s: %s in %.0f s, counted in its run time." % (r["build"].name, r["setup"][0], r["setup"][1]))
    lines.append("")
    total = time.time() - start
    device_error = device_cells is not None and any(c[0] == "error" for c in device_cells.values())
    device_diff = device_cells is not None and any(c[0] == "diff" for c in device_cells.values())
    if device_error:
        detail.append("the device: " + "; ".join("%s: %s" % (s, c[1]) for s, c in device_cells.items() if c[0] == "error"))
    if device_diff:
        detail.append("the device differs: " + ", ".join("%s %s" % (s, c[1]) for s, c in device_cells.items() if c[0] == "diff"))
    if failures or diffs or device_error or device_diff:
        lines.append("**FAILED**: %d build(s) could not be made or run, %d build(s) differ%s." % (
            len(failures) + device_error, len(diffs) + device_diff, " (the device counted)" if device_cells else ""))
        for r in failures:
            lines.append("- %s: %s" % (r["build"].name, r["error"]))
        lines.extend("- " + d for d in detail)
    else:
        lines.append("**CERTIFIED**: %d builds x %d scenes agree with the vectors on every certified frame (%.0f s)."
                     % (len(results) + (device_cells is not None), len(scenes), total))
    if skipped:
        lines.append("")
        lines.append("**SKIPPED** (not certified here: tools not installed): %s."
                     % "; ".join("%s (%s)" % (x["build"].name, x["skipped"]) for x in skipped))
    report = "\n".join(lines)
    print()
    print(report)
    if args.report:
        with open(args.report, "w", encoding="utf-8") as f:
            f.write(report + "\n")
    if failures or device_error:
        return 2
    return 1 if diffs or device_diff else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
