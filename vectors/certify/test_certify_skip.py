#!/usr/bin/env python3
"""Test of certify.py's builds beyond Linux where their tools are missing:
they are listed (--list); named in --builds without their tools they are an
error (exit 2) naming each missing tool and its Debian package; with
--skip-missing each is skipped with a message naming it and what is missing,
shown as SKIPPED in the report, never silently, while the builds that can run
are certified. The missing tools are hidden by a PATH of links to every
command on PATH but em++, wine and x86_64-w64-mingw32-g++, with a node that
must never run and a clang++ that finds no wasm32-wasi sysroot; so the result
is the same whether or not this machine has them; the full matrix, too, skips
them by itself. One native g++ -O0 build of one scene.

  python3 vectors/certify/test_certify_skip.py WORKDIR
"""

import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CERTIFY = os.path.join(HERE, "certify.py")
NEW_BUILDS = ["wasm32-emscripten-O2", "wasm32-emscripten-O3", "wasm32-wasi-clang-O2", "wasm32-wasi-clang-O3",
              "win64-gcc-O2", "win64-gcc-O3-fast-math"]
HIDDEN = {"em++", "wine", "x86_64-w64-mingw32-g++", "node", "clang++"}


def fake_path(directory):
    """A directory of links to every command on PATH but HIDDEN, a node that
    fails if run, and a clang++ with a sysroot that does not exist."""
    if os.path.exists(directory):
        shutil.rmtree(directory)
    os.makedirs(directory)
    for d in os.environ.get("PATH", "").split(os.pathsep):
        if not os.path.isdir(d):
            continue
        for name in sorted(os.listdir(d)):
            target = os.path.join(d, name)
            link = os.path.join(directory, name)
            if name in HIDDEN or os.path.lexists(link) or not os.access(target, os.X_OK) or os.path.isdir(target):
                continue
            os.symlink(target, link)
    with open(os.path.join(directory, "node"), "w", encoding="utf-8") as f:
        f.write("#!/bin/sh\necho 'test_certify_skip: node must not run for a skipped build' >&2\nexit 99\n")
    scripts = ["node"]
    clang = shutil.which("clang++")
    if clang:
        with open(os.path.join(directory, "clang++"), "w", encoding="utf-8") as f:
            f.write("#!/bin/sh\nexec %s --sysroot=/nonexistent-wasi-sysroot \"$@\"\n" % clang)
        scripts.append("clang++")
    for s in scripts:
        os.chmod(os.path.join(directory, s), 0o755)
    return clang is not None


def certify(args, path=None):
    env = dict(os.environ)
    if path:
        env["PATH"] = path
    p = subprocess.run([sys.executable, CERTIFY] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       env=env)
    print("$ certify.py %s\nexit %d\n%s%s" % (" ".join(args), p.returncode, p.stdout, p.stderr))
    return p


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    work = os.path.abspath(argv[1])
    os.makedirs(work, exist_ok=True)
    bindir = os.path.join(work, "path")
    have_clang = fake_path(bindir)
    checks = []

    listed = certify(["--list"])
    names = [line.split()[0] for line in listed.stdout.splitlines() if line.strip()]
    checks += [(b in names, "--list names " + b) for b in NEW_BUILDS]

    # Named explicitly, a build whose tools are missing is an error.
    named = certify(["--builds", "win64-gcc-O2,wasm32-emscripten-O2", "--scenes", "drop",
                     "--work", os.path.join(work, "named")], bindir)
    checks += [
        (named.returncode == 2, "named builds without their tools: exit 2 (got %d)" % named.returncode),
        ("not installed: em++, wine, x86_64-w64-mingw32-g++, needed by win64-gcc-O2, wasm32-emscripten-O2"
         in named.stderr, "the error names each missing tool and the builds that need it"),
        ("apt-get install" in named.stderr and "g++-mingw-w64-x86-64" in named.stderr and "wine64" in named.stderr
         and "emscripten" in named.stderr, "the error names the Debian packages"),
    ]

    # --skip-missing: skipped, each named, and the rest certified.
    wanted = ["x86_64-gcc-O0", "wasm32-emscripten-O2", "win64-gcc-O2"] + (["wasm32-wasi-clang-O2"] if have_clang else [])
    skip = certify(["--builds", ",".join(wanted), "--scenes", "drop", "--skip-missing",
                    "--work", os.path.join(work, "skip")], bindir)
    out = skip.stdout
    checks += [
        (skip.returncode == 0, "--skip-missing: exit 0 (got %d)" % skip.returncode),
        ("certify: SKIPPED wasm32-emscripten-O2: not installed: em++ (Debian: apt-get install emscripten)" in out,
         "the emscripten build is skipped with a message naming em++"),
        ("certify: SKIPPED win64-gcc-O2: not installed: x86_64-w64-mingw32-g++, wine "
         "(Debian: apt-get install g++-mingw-w64-x86-64 wine wine64)" in out,
         "the Windows build is skipped with a message naming mingw-w64 and wine"),
        ("| `win64 gcc -O2` | SKIPPED: not installed: x86_64-w64-mingw32-g++, wine |" in out,
         "the report's table shows the Windows build SKIPPED"),
        ("| `x86_64 gcc -O0` | all 300 |" in out, "the native build is certified"),
        ("**CERTIFIED**: 1 builds x 1 scenes" in out, "one build certified"),
        ("**SKIPPED** (not certified here: tools not installed): wasm32-emscripten-O2" in out,
         "the verdict lists the skipped builds"),
        ("node must not run" not in skip.stderr + out, "no skipped build was run"),
    ]
    if have_clang:
        checks.append(("certify: SKIPPED wasm32-wasi-clang-O2: not installed: the wasm32-wasi sysroot" in out,
                       "a clang++ without the wasm32-wasi sysroot skips the wasi build, naming the sysroot"))
    # The full matrix (no --builds, no --skip-missing) skips them by itself,
    # each named, before it reads the vectors (none here: it stops there, with
    # nothing built). Needs the Linux matrix's compilers and qemu (.ci/packages).
    sys.dont_write_bytecode = True  # nothing written into the source tree
    sys.path.insert(0, HERE)
    import certify as c  # pylint: disable=import-outside-toplevel
    linux_tools = sorted({t for b in c.matrix_full() if not b.arch.optional for t in b.tools()})
    absent = [t for t in linux_tools if shutil.which(t, path=bindir) is None]
    if absent:
        print("note: %s not installed here; the full-matrix check is not run" % ", ".join(absent))
    else:
        full = certify(["--vectors", os.path.join(work, "no-vectors"), "--work", os.path.join(work, "full")], bindir)
        checks += [("certify: SKIPPED %s: not installed: " % b in full.stdout,
                    "the full matrix skips %s with a message" % b) for b in NEW_BUILDS]
        checks.append(("no scene vectors in" in full.stderr and full.returncode == 2,
                       "the full matrix went on past the skipped builds (to the missing vectors: exit 2)"))
    failed = [m for ok, m in checks if not ok]
    for m in failed:
        print("FAILED: " + m, file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
