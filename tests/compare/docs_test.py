#!/usr/bin/env python3
"""The docs against the code.

constants  docs/SCENES.md's constants table: every key of lockstep::Constants
           (as `lockstep run` writes them into the run record's scene, all of
           them, at their defaults for a scene that sets none) is in the
           table with the code's default, the table has no other key, and the
           "All N" line counts them. Exit codes: the README lists those of
           `lockstep --help`. docs/README.md names every file in docs/.
tour       the README's five-minute tour (the ```sh block after
           "<!-- tour -->"): every command runs and exits 0, in WORKDIR (under
           the build tree), with ./build/compare/lockstep replaced by LOCKSTEP.

usage: docs_test.py constants|tour LOCKSTEP WORKDIR
"""
import json
import os
import re
import shutil
import subprocess
import sys

WHAT, LOCKSTEP, WORK = sys.argv[1], os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3])
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def run(*args):
    return subprocess.run([LOCKSTEP, *args], capture_output=True, text=True, cwd=WORK, timeout=600)


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
readme = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()

if WHAT == "constants":
    # The code's defaults: a scene that sets no constant, written back by `lockstep run`.
    scene = {"format": "lockstep-scene", "version": 1, "name": "defaults", "frames": 1,
             "bodies": [{"half_extents": [0.5, 0.5, 0.5], "position": [0, 2, 0]}]}
    with open(os.path.join(WORK, "defaults.json"), "w") as f:
        json.dump(scene, f)
    p = run("run", "defaults.json", "--frames", "0", "--out", "d.csv", "--no-progress")
    check(p.returncode == 0, "lockstep run defaults.json (%s)" % p.stderr)
    code = json.load(open(os.path.join(WORK, "d.csv.run.json")))["scene"]["constants"]

    text = open(os.path.join(ROOT, "docs", "SCENES.md"), encoding="utf-8").read()
    section = text[text.index("## Constants"):]
    section = section[:section.index("\n## ", 1)]
    rows = re.findall(r"^\| `([a-z_]+)` \| ([^|]+) \|", section, re.M)
    doc = {}
    for key, default in rows:
        default = default.strip()
        if "=" in default:  # "1/60 = 0.016666666666666666"
            default = default.split("=")[-1].strip()
        doc[key] = json.loads(default)
    for key, value in code.items():
        check(key in doc, "SCENES.md's constants table lists %s" % key)
        if key in doc:
            same = (doc[key] == value if isinstance(value, list) or isinstance(value, int)
                    else abs(doc[key] - value) <= 1e-12 * max(1.0, abs(value)))
            check(same, "SCENES.md's default of %s is the code's %s (the table says %s)" % (key, value, doc[key]))
    for key in doc:
        check(key in code, "SCENES.md's constant %s exists in the code" % key)
    count = re.search(r"All (\d+)\b", section)
    check(count is not None and int(count.group(1)) == len(code),
          "SCENES.md says 'All %d' constants (says %s)" % (len(code), count and count.group(1)))
    print("constants: %d in the code, %d in SCENES.md's table" % (len(code), len(doc)))

    # Every exit code of `lockstep --help` is in the README (and SCENES/COMPARE need not repeat it).
    codes = re.findall(r"(?:^\s*|; )(\d) ", run("--help").stdout.split("exit codes:")[-1])
    check(sorted(set(codes)) == ["0", "1", "2", "3"], "lockstep --help lists exit codes 0-3 (got %s)" % codes)
    for c in codes:
        check(re.search(r"\b%s (success|the engines disagree|a usage|a run stopped)" % c, readme) is not None,
              "the README lists exit code %s" % c)

    # docs/README.md, the index, names every file in docs/.
    index = open(os.path.join(ROOT, "docs", "README.md"), encoding="utf-8").read()
    for name in sorted(os.listdir(os.path.join(ROOT, "docs"))):
        if name != "README.md" and (name.endswith(".md") or os.path.isdir(os.path.join(ROOT, "docs", name))):
            check(name in index, "docs/README.md names %s" % name)
    # The README is a front page: at most about 250 lines.
    check(len(readme.splitlines()) <= 260, "README.md has at most ~250 lines (has %d)" % len(readme.splitlines()))
    # The URL parameters of the replay page are documented.
    compare_md = open(os.path.join(ROOT, "docs", "COMPARE.md"), encoding="utf-8").read()
    for param in ["#frame=", "#mode=side", "#select=", "#only=", "#run="]:
        check(param in compare_md, "docs/COMPARE.md documents the page's %s" % param)

elif WHAT == "tour":
    block = re.search(r"<!-- tour -->\s*```sh\n(.*?)```", readme, re.S)
    check(block is not None, "the README has a tour block (<!-- tour --> then ```sh)")
    commands = [l.split("  #")[0].strip() for l in (block.group(1) if block else "").splitlines() if l.strip()]
    check(len(commands) >= 4, "the tour has its commands (got %d)" % len(commands))
    for c in commands:
        args = c.split()
        check(args[0] == "./build/compare/lockstep", "tour command runs lockstep: %r" % c)
        p = run(*args[1:])
        check(p.returncode == 0, "tour: %r exits 0 (got %d: %s)" % (c, p.returncode, p.stderr[-300:]))
        print("tour: %s -> %d" % (c, p.returncode))
    for out in ["fixed.csv", "float.csv", "stack5.html", "bowl/index.html"]:
        check(os.path.exists(os.path.join(WORK, out)), "the tour writes %s" % out)
else:
    sys.exit("usage: docs_test.py constants|tour LOCKSTEP WORKDIR")

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("docs_test %s: all checks passed" % WHAT)
