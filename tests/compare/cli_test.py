#!/usr/bin/env python3
"""The `lockstep` command line: every command answers --help with usage,
options, defaults and an example; a bad option, a missing value or a bad number
is one line on stderr naming the option and what it allows (exit 2); `run`
writes CSV, JSON lines (parsed here), hashes and the run record, and --quiet
prints one final line; `view` and `compare --report` write the replay page,
whose data match the CSV and the harness.

usage: cli_test.py LOCKSTEP WORKDIR
"""
import base64
import csv
import json
import os
import re
import shutil
import struct
import subprocess
import sys

LOCKSTEP, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
COMMANDS = ["accuracy", "certify", "compare", "run", "scenes", "vectors", "view"]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def run(*args, cwd=None):
    return subprocess.run([LOCKSTEP, *args], capture_output=True, text=True, cwd=cwd or WORK, timeout=300)


def page_data(path):
    html = open(path, encoding="utf-8").read()
    m = re.search(r'<script id="lockstep-data" type="application/json">(.*?)</script>', html, re.S)
    return json.loads(m.group(1))


def floats(b64):
    raw = base64.b64decode(b64)
    return struct.unpack("<%df" % (len(raw) // 4), raw)


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)

# --help: usage, every option with its description, defaults, an example.
top = run("--help")
check(top.returncode == 0 and all(c in top.stdout for c in COMMANDS), "lockstep --help lists every command")
for c in COMMANDS:
    h = run(c, "--help")
    check(h.returncode == 0, "%s --help exits 0" % c)
    check("Usage: lockstep %s" % c in h.stdout, "%s --help shows its usage" % c)
    check(re.search(r"Example:\n(  lockstep .*\n)*  lockstep %s " % c, h.stdout) is not None, "%s --help ends with an example of itself" % c)
    check("Options:" in h.stdout and "--help" in h.stdout, "%s --help lists options" % c)
h = run("run", "--help").stdout
check("=fixed" in h and "=csv" in h and "=1" in h, "run --help shows the defaults of --engine, --format, --every")

# Usage errors: one line, naming the option and what it allows; exit 2.
for args, must in [
    (["run", "--frames", "abc"], ["--frames", "'abc'", "integer in [0, 10000000]"]),
    (["run", "--frames", "-5"], ["--frames", "'-5'", "integer in [0, 10000000]"]),
    (["run", "--every", "0"], ["--every", "integer in [1, 1000000]"]),
    (["run", "--frames"], ["--frames", "needs a value", "integer in [0, 10000000]"]),
    (["run", "--bogus"], ["unknown option --bogus", "--engine"]),
    (["run", "--engine", "quantum"], ["--engine", "'quantum'", "fixed, float, double, mp"]),
    (["run", "--format", "xml"], ["--format", "csv, jsonl"]),
    (["run", "--threads", "0"], ["--threads", "'0'", "integer in [1, 256]"]),
    (["run", "stack5", "--engine", "gpu", "--threads", "2", "--quiet"], ["--threads 2", "gpu engine", "give 1"]),
    (["compare", "--engines", "fixed,nope", "--no-report"], ["--engines", "'nope'", "fixed"]),
    (["compare", "--max-failures", "1e3"], ["--max-failures", "'1e3'", "integer in [0, 1000000]"]),
    (["vectors", "frob", "dir"], ["ACTION", "'frob'", "generate, verify"]),
    (["view"], ["RUN", "required"]),
    (["view", "missing.csv"], ["missing.csv.run.json", "lockstep run"]),
    (["accuracy", "--timing-runs", "0"], ["--timing-runs", "integer in [1, 1000]"]),
    (["nope"], ["unknown command 'nope'", "run"]),
    (["scenes", "a", "b"], ["unexpected argument 'b'", "it takes SCENE"]),
    (["compare", "drop", "--engines", "fixed,float", "--baseline", "double", "--no-report"], ["--baseline", "'double'"]),
]:
    p = run(*args)
    lines = p.stderr.strip().splitlines()
    check(p.returncode == 2, "%s exits 2 (got %d)" % (args, p.returncode))
    check(len(lines) == 1, "%s: one line on stderr (got %r)" % (args, p.stderr))
    for m in must:
        check(m in p.stderr, "%s: the error names %r (got %r)" % (args, m, p.stderr))

# run: the summary line that scripts read (gpu/bench/schedule_table.py), the CSV, hashes and run record.
p = run("run", "stack5", "--engine", "fixed", "--frames", "50", "--every", "10", "--out", "s.csv", "--no-progress")
check(p.returncode == 0, "run stack5 exits 0")
summary = re.match(r"scene stack5, engine fixed: 50 frames, 5 bodies, [0-9.]+ ms/step \(stepping only\), final hash "
                   r"([0-9a-f]{16}), (all asleep at frame \d+|not all asleep)$", p.stdout.splitlines()[0])
check(summary is not None, "run prints its summary line (got %r)" % p.stdout)
rows = list(csv.DictReader(open(os.path.join(WORK, "s.csv"))))
check(sorted({int(r["frame"]) for r in rows}) == [0, 10, 20, 30, 40, 50], "--every 10 writes frames 0, 10, ..., 50")
hashes = dict(l.strip().split(",") for l in open(os.path.join(WORK, "s.csv.hashes")).readlines()[1:])
record = json.load(open(os.path.join(WORK, "s.csv.run.json")))
check(record["format"] == "lockstep-run" and record["frames_run"] == 50 and record["every"] == 10,
      "the run record names its format, frames and stride")
check(all(record["hash"][int(f)] == h for f, h in hashes.items()), "the run record's hashes are the .hashes file's")
check(summary and record["hash"][50] == summary.group(1), "the run record's last hash is the final hash")

# --threads N: the same bits for every N (docs/SPEC.md 7.7 "Threads").
hashes_by_threads = []
for n in ("1", "3"):
    t = run("run", "pyramid", "--frames", "80", "--threads", n, "--quiet", "--out", "t%s.csv" % n)
    m = re.search(r"hash ([0-9a-f]{16})", t.stdout)
    hashes_by_threads.append(m.group(1) if m else None)
    check(t.returncode == 0 and m is not None, "run --threads %s exits 0 with its line (got %r %r)" % (n, t.stdout, t.stderr))
check(hashes_by_threads[0] is not None and hashes_by_threads[0] == hashes_by_threads[1],
      "run --threads 3 gives the hash of --threads 1 (got %r)" % hashes_by_threads)
check(open(os.path.join(WORK, "t1.csv.hashes")).read() == open(os.path.join(WORK, "t3.csv.hashes")).read(),
      "every frame's hash is the same on 1 and 3 threads")

# --quiet: one line (frames, ms/step, hash, all-asleep frame, worst penetration); on stderr with --out -.
q = run("run", "drop", "--quiet", "--out", "d.csv")
m = re.fullmatch(r"drop fixed: 300 frames, [0-9.]+ ms/step, hash ([0-9a-f]{16}), (all asleep at frame \d+|not all asleep), "
                 r"worst penetration ([0-9.e+-]+) m\n", q.stdout)
check(q.returncode == 0 and m is not None and q.stderr == "", "run --quiet prints one final line (got %r %r)" % (q.stdout, q.stderr))
check(m is not None and float(m.group(3)) > 0, "drop's worst penetration is above 0 (the cube lands)")
q2 = run("run", "drop", "--quiet", "--out", "-")
check(q2.stdout.startswith("frame,body,") and q2.stderr.startswith("drop fixed: 300 frames"),
      "run --quiet --out -: the trajectory alone on stdout, the line on stderr")

# JSON lines through nlohmann: every line parses; the hash of each frame is the CSV run's.
j = run("run", "stack5", "--frames", "50", "--format", "jsonl", "--out", "-", "--no-progress")
frames = [json.loads(l) for l in j.stdout.splitlines()]
check(len(frames) == 51 and all(len(f["bodies"]) == 5 for f in frames), "jsonl: 51 frames of 5 bodies")
check(all(record["hash"][f["frame"]] == f["hash"] for f in frames), "jsonl hashes equal the CSV run's")
raw = [json.loads(l) for l in run("run", "stack5", "--frames", "5", "--format", "jsonl", "--raw", "--out", "-").stdout.splitlines()]
check(all(isinstance(x, int) for x in raw[-1]["bodies"][0]["p"]), "jsonl --raw writes integers")
check(abs(raw[0]["bodies"][0]["p"][1] / 65536 - frames[0]["bodies"][0]["p"][1]) < 1e-9, "--raw / 2^16 is the decimal value")

# view: the page's data are the CSV's states (as float32), its runs, and the hash comparison of two fixed runs.
run("run", "stack5", "--frames", "50", "--out", "a.csv", "--contacts", "--no-progress")
run("run", "stack5", "--frames", "50", "--out", "b.csv", "--no-progress")
run("run", "stack5", "--frames", "50", "--engine", "double", "--out", "c.csv", "--no-progress")
v = run("view", "a.csv", "c.csv", "b.csv", "--out", "v.html")
check(v.returncode == 0 and "v.html (3 runs of scene 'stack5', 5 bodies, 51 frames kept" in v.stdout, "view reports the page (got %r %r)" % (v.stdout, v.stderr))
d = page_data(os.path.join(WORK, "v.html"))
check([r["label"] for r in d["runs"]] == ["a.csv", "c.csv", "b.csv"], "the page holds the runs in order")
states = floats(d["runs"][1]["state"])
rows_c = [r for r in csv.DictReader(open(os.path.join(WORK, "c.csv"))) if r["frame"] == "37"]
got = states[(37 * 5 + 3) * 13:(37 * 5 + 3) * 13 + 13]
want = [float(rows_c[3][k]) for k in ["px", "py", "pz", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz"]]
check(all(abs(g - w) <= 1e-6 * max(1, abs(w)) for g, w in zip(got, want)), "page state of body 3 at frame 37 = the CSV's")
check(d["comparison"]["hash_run_a"] == 0 and d["comparison"]["hash_run_b"] == 2 and
      d["comparison"]["first_hash_difference"] == -1, "the page compares the hashes of the two fixed runs: identical")
check("0" in d["runs"][0]["contacts"] and "0" not in d["runs"][2]["contacts"], "contacts only where recorded (--contacts)")
small = run("view", "a.csv", "--max-mb", "1", "--out", "one.html")
check(small.returncode == 0 and os.path.exists(os.path.join(WORK, "one.html")), "view of one run")
other = run("run", "drop", "--frames", "10", "--out", "drop.csv", "--no-progress")
mix = run("view", "a.csv", "drop.csv")
check(mix.returncode == 2 and "another scene" in mix.stderr, "view refuses runs of two scenes (got %r)" % mix.stderr)

# compare --report: index.html beside the CSVs and SVGs; its parted frame is the harness's.
cmp = run("compare", "bowl", "--engines", "fixed,double", "--frames", "100", "--report", "rep", "--no-progress")
part = re.search(r"^fixed .* frame (\d+), body (\d+) ", cmp.stdout, re.M)
check(part is not None, "the harness reports where fixed parts from double on bowl")
d = page_data(os.path.join(WORK, "rep", "index.html"))
check([r["label"] for r in d["runs"]] == ["double", "fixed"], "the baseline first")
check(part and d["comparison"]["parted_frame"][1] == int(part.group(1)) and d["comparison"]["parted_body"][1] == int(part.group(2)),
      "the page's parted frame and body are the harness's")
for f in ["divergence.svg", "energy.svg", "sleep_timeline.svg", "frames.csv"]:
    check(os.path.exists(os.path.join(WORK, "rep", f)), "the report still has " + f)


def engine_limits():
    """Issue 30: a scene the loader accepts but whose bodies the fixed engine's
    Q16.16 cannot hold (docs/SCENES.md "Ranges per number type"): `run --engine
    fixed` refuses it with the field, the value, the limit and a fix (exit 2),
    double runs it, and `compare` shows fixed as a failed column with the
    reason and still judges the others (exit 1)."""
    def scene(name, body):
        path = os.path.join(WORK, name + ".json")
        with open(path, "w") as f:
            json.dump({"format": "lockstep-scene", "version": 1, "name": name, "frames": 60,
                       "bodies": [dict(body, position=[0, 2, 0]), {"position": [3, 0.5, 0]}]}, f)
        return path
    cases = [
        (scene("tiny_mass", {"mass": 1e-05}), "bodies[0].mass",
         ["bodies[0].mass = 1e-05 kg", "inverse mass 1/m = 100000 1/kg", "|x| < 32768", "use a mass of at least 0.000176 kg"]),
        (scene("light_cube", {"mass": 1e-04}), "bodies[0].mass",
         ["bodies[0].mass = 0.0001 kg", "inverse inertia I_x^-1", "= 60000 1/(kg m^2)", "use a mass of at least 0.000176 kg"]),
        (scene("small_cube", {"half_extents": [0.00390625] * 3}), "bodies[0].half_extents",
         ["bodies[0].half_extents = [0.00390625, 0.00390625, 0.00390625] m", "3/(h_y^2 + h_z^2) = 98304",
          "make every half extent at least 0.00731 m"]),
    ]
    for path, field, parts in cases:
        name = os.path.basename(path)
        r = run("run", path, "--engine", "fixed", "--out", name + ".csv", "--no-progress")
        check(r.returncode == 2, "%s: run --engine fixed exits 2 (got %d: %r)" % (name, r.returncode, r.stderr))
        check(r.stderr.startswith("lockstep run: scene error: ") and r.stderr.count("\n") == 1,
              "%s: one line on stderr, a scene error (got %r)" % (name, r.stderr))
        for p in parts + ["or run on float or double"]:
            check(p in r.stderr, "%s: the refusal says %r (got %r)" % (name, p, r.stderr))
        check("overflow" not in r.stderr and "frame 0" not in r.stderr, "%s: refused before frame 0, not an overflow" % name)
        check(not os.path.exists(os.path.join(WORK, name + ".csv")), "%s: no trajectory written" % name)
        d = run("run", path, "--engine", "double", "--quiet", "--out", name + "-double.csv")
        check(d.returncode == 0 and "60 frames" in d.stdout, "%s: double runs it (got %r %r)" % (name, d.stdout, d.stderr))
        c = run("compare", path, "--engines", "fixed,float,double", "--report", name + "-rep", "--no-progress")
        check(c.returncode == 1, "%s: compare exits 1, the comparison failed (got %d: %r)" % (name, c.returncode, c.stderr))
        check(re.search(r"^fixed +[0-9.]+ +- +- +- +- +cannot run +FAILED$", c.stdout, re.M) is not None,
              "%s: fixed is a failed column (got %r)" % (name, c.stdout))
        check("FAILED, cannot run this scene: " in c.stdout and parts[0] in c.stdout,
              "%s: the summary gives the reason" % name)
        fl = re.search(r"^float .* never +(\d+)/(\d+)$", c.stdout, re.M)
        check(fl is not None and fl.group(1) == fl.group(2) and int(fl.group(2)) > 0,
              "%s: float is still judged against double, and agrees (got %r)" % (name, c.stdout))
        check("DISAGREE: %s, 1 failed check" % os.path.splitext(name)[0] in c.stdout, "%s: one failed check, fixed's" % name)
        rows = list(csv.DictReader(open(os.path.join(WORK, name + "-rep", "checks.csv"))))
        fixed_rows = [x for x in rows if x["engine"] == "fixed"]
        check(len(fixed_rows) == 1 and fixed_rows[0]["check"] == "run" and fixed_rows[0]["quantity"] == field and
              fixed_rows[0]["pass"] == "0" and "cannot run this scene" in fixed_rows[0]["value"],
              "%s: checks.csv: fixed's run check names %s" % (name, field))
        pd = page_data(os.path.join(WORK, name + "-rep", "index.html"))
        check([x["label"] for x in pd["runs"]] == ["double", "float"], "%s: the replay page holds the engines that ran" % name)
    # Two engines, fixed one of them: compare still reports and judges, exit 1 (not an abort).
    c = run("compare", cases[0][0], "--engines", "fixed,double", "--no-report", "--no-progress")
    check(c.returncode == 1 and "cannot run" in c.stdout and "double" in c.stdout, "compare fixed,double: fixed fails, exit 1")


engine_limits()

# --version: the version, the commit, the engines built and how the gpu engine was built.
ver = run("--version")
check(ver.returncode == 0 and re.search(r"^lockstep \d+\.\d+\.\d+$", ver.stdout, re.M) and
      re.search(r"^commit [0-9a-f]{7,}", ver.stdout, re.M) and re.search(r"^engines fixed, float, double, mp", ver.stdout, re.M)
      and re.search(r"^gpu engine: (CUDA|host build only|not built)", ver.stdout, re.M),
      "lockstep --version names version, commit, engines and CUDA (got %r)" % ver.stdout)

# Every exit code in the top-level and every command's --help.
for args in [["--help"]] + [[c, "--help"] for c in COMMANDS]:
    h = run(*args).stdout
    check(all(x in h for x in ["exit codes: 0 ", "1 the engines disagree", "2 a usage", "3 a run stopped"]),
          "%s lists every exit code (0, 1, 2, 3)" % " ".join(args))

# "did you mean" for a mistyped option, in command-line order.
p = run("run", "--engin", "double")
check(p.returncode == 2 and "unknown option --engin; did you mean --engine?" in p.stderr and "double --engin" not in p.stderr,
      "a mistyped option gets a did-you-mean (got %r)" % p.stderr)
p = run("compare", "--page-mbb", "3", "--no-report")
check(p.returncode == 2 and "did you mean --page-mb?" in p.stderr, "compare --page-mbb: did you mean --page-mb (got %r)" % p.stderr)
p = run("veiw")
check(p.returncode == 2 and "did you mean view?" in p.stderr, "a mistyped command gets a did-you-mean (got %r)" % p.stderr)

# A bare NaN or Infinity in a scene: not allowed, said so, with line and column.
for word in ["NaN", "Infinity", "-Infinity", "nan"]:
    with open(os.path.join(WORK, "nan.json"), "w") as f:
        f.write('{"format": "lockstep-scene", "version": 1, "name": "n", "frames": 10,\n'
                ' "bodies": [{"half_extents": [0.5, 0.5, 0.5], "position": [0, %s, 0]}]}\n' % word)
    p = run("run", "nan.json", "--out", "nan.csv")
    check(p.returncode == 2 and ("%s is not allowed" % word) in p.stderr and "finite" in p.stderr and ":2:" in p.stderr,
          "a bare %s in a scene is reported as not allowed (got %r)" % (word, p.stderr))

# Wording: "1 body", significant digits for ms/step, "not all asleep".
p = run("run", "drop", "--frames", "10", "--out", "d1.csv", "--no-progress")
check(", 1 body, " in p.stdout and "not all asleep" in p.stdout, "run drop: '1 body', 'not all asleep' (got %r)" % p.stdout)
ms = re.search(r"([0-9.]+) ms/step", p.stdout)
digits = ms and ms.group(1).replace(".", "").lstrip("0")
check(ms is not None and (ms.group(1) == "0" or len(digits) >= 3), "ms/step has 3 significant digits (got %r)" % p.stdout)
q = run("run", "drop", "--frames", "10", "--quiet", "--out", "d2.csv")
check("not all asleep" in q.stdout and "at never" not in q.stdout, "run --quiet: 'not all asleep' (got %r)" % q.stdout)

# --quiet means no notes: compare prints nothing on stderr (the gpu engine's host-build note included).
engines = "fixed,gpu" if "gpu" in ver.stdout.split("engines ", 1)[-1].split("\n")[0] else "fixed,float"
p = run("compare", "stack5", "--engines", engines, "--frames", "20", "--quiet", "--no-report")
check(p.returncode in (0, 1) and p.stderr == "", "compare --quiet (%s): nothing on stderr (got %r)" % (engines, p.stderr))
p = run("run", "stack5", "--engine", engines.split(",")[1], "--frames", "5", "--quiet", "--out", "q.csv")
check(p.stderr == "", "run --quiet: nothing on stderr (got %r)" % p.stderr)

# One name for the page size: --page-mb in compare and view; --max-mb still accepted in both.
for args in [["view", "a.csv", "--page-mb", "2", "--out", "pm.html"], ["view", "a.csv", "--max-mb", "2", "--out", "pm2.html"],
             ["compare", "stack5", "--engines", "fixed,double", "--frames", "5", "--max-mb", "2", "--report", "pm", "--no-progress"]]:
    p = run(*args)
    check(p.returncode == 0, "%s is accepted (got %r)" % (" ".join(args), p.stderr))
check("--page-mb" in run("view", "--help").stdout and "--page-mb" in run("compare", "--help").stdout,
      "view and compare --help name --page-mb")

# accuracy --machine: the CPU's model name from /proc/cpuinfo by default.
model = None
if os.path.exists("/proc/cpuinfo"):
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            model = line.split(":", 1)[1].strip()
            break
if model:
    check(model in run("accuracy", "--help").stdout, "accuracy --machine defaults to this CPU, %r" % model)

# compare's resting report: every cube of a settled stack rests on the one below (never "none").
p = run("compare", "stack5", "--engines", "fixed,double", "--frames", "200", "--report", "st5", "--no-progress")
rows = list(csv.DictReader(open(os.path.join(WORK, "st5", "bodies.csv"))))
sup = {(r["engine"], int(r["body"])): r["support"] for r in rows}
check(all(sup.get((e, 0)) == "ground" for e in ["fixed", "double"]), "stack5: the bottom cube rests on the ground (got %s)" % sup)
check(all(sup.get((e, i)) == "body %d" % (i - 1) for e in ["fixed", "double"] for i in range(1, 5)),
      "stack5: each cube rests on the one below (got %s)" % sup)

# Runs written with different --every are compared on their common frames, in either order.
run("run", "bowl", "--engine", "fixed", "--frames", "150", "--out", "bowl-fixed.csv", "--no-progress")
run("run", "bowl", "--engine", "double", "--frames", "150", "--every", "10", "--out", "bowl10-double.csv", "--no-progress")
v1 = run("view", "bowl-fixed.csv", "bowl10-double.csv", "--out", "b1.html")
v2 = run("view", "bowl10-double.csv", "bowl-fixed.csv", "--out", "b2.html")
f1 = re.search(r"parts from bowl-fixed.csv at frame (\d+)", v1.stdout)
f2 = re.search(r"parts from bowl10-double.csv at frame (\d+)", v2.stdout)
check(f1 is not None and f2 is not None and f1.group(1) == f2.group(1),
      "view of runs with different --every: they part at the same frame in either order (got %r / %r)" % (v1.stdout, v2.stdout))
check("frames both runs hold" in v1.stdout and "trajectory tolerance" in v1.stdout and "rest tolerance" in v1.stdout,
      "view says which frames and which tolerances it compared (got %r)" % v1.stdout)
d = page_data(os.path.join(WORK, "b1.html"))
check(d["comparison"]["tolerance_name"] == "trajectory tolerance" and "trajectory tolerance" in d["comparison"]["tolerance_note"],
      "the page names the tolerance it judges against")


def snapshots():
    """Issue 32: `run SCENE --frames N --save-state FILE` then `run --load-state
    FILE --frames N` gives the hashes of frames N+1..2N of `run SCENE --frames
    2N`, on fixed and double (frame numbers go on); the CSV starts at frame N;
    a bad, foreign or unreadable snapshot is one line on stderr (exit 2)."""
    def hashes(path):
        return open(os.path.join(WORK, path)).read().splitlines()[1:]
    for engine, scene, n in [("fixed", "pyramid", 40), ("double", "tip_corner", 25), ("float", "bowl", 30),
                             ("gpu-fixed", "stack5", 30)]:
        full = run("run", scene, "--engine", engine, "--frames", str(2 * n), "--out", "full-%s.csv" % engine, "--quiet")
        first = run("run", scene, "--engine", engine, "--frames", str(n), "--out", "first-%s.csv" % engine, "--quiet",
                    "--save-state", "state-%s.bin" % engine)
        rest = run("run", "--load-state", "state-%s.bin" % engine, "--frames", str(n), "--out", "rest-%s.csv" % engine, "--quiet")
        check(full.returncode == 0 and first.returncode == 0 and rest.returncode == 0,
              "snapshots %s: the three runs exit 0 (got %r %r %r)" % (engine, full.stderr, first.stderr, rest.stderr))
        if rest.returncode != 0:
            continue
        h_full, h_rest = hashes("full-%s.csv.hashes" % engine), hashes("rest-%s.csv.hashes" % engine)
        check(len(h_rest) == n and h_rest == h_full[n:],
              "snapshots %s/%s: run to %d = run to %d + resume %d (hashes lines; got %r vs %r)"
              % (engine, scene, 2 * n, n, n, h_rest[:2], h_full[n:n + 2]))
        check(h_full[n:] != h_full[n - 1:-1], "snapshots %s/%s: the scene still moves after frame %d" % (engine, scene, n))
        rows = list(csv.DictReader(open(os.path.join(WORK, "rest-%s.csv" % engine))))
        check(rows and rows[0]["frame"] == str(n) and rows[-1]["frame"] == str(2 * n),
              "snapshots %s: the resumed trajectory runs from frame %d to %d" % (engine, n, 2 * n))
        check(("%s %s: %d frames" % (scene, engine, 2 * n)) in rest.stdout, "snapshots %s: the summary counts frames on (got %r)"
              % (engine, rest.stdout))
    bad = os.path.join(WORK, "bad-state.bin")
    blob = bytearray(open(os.path.join(WORK, "state-fixed.bin"), "rb").read())
    blob[len(blob) // 2] ^= 1
    open(bad, "wb").write(bytes(blob))
    open(os.path.join(WORK, "short-state.bin"), "wb").write(bytes(blob[:30]))
    for args, says in [(["--load-state", "bad-state.bin"], "checksum"),
                       (["--load-state", "short-state.bin"], "truncated"),
                       (["--load-state", "full-fixed.csv"], "not a lockstep snapshot"),
                       (["--load-state", "missing.bin"], "cannot read 'missing.bin'"),
                       (["--load-state", "state-fixed.bin", "--engine", "float"], "a snapshot of the fixed engine"),
                       (["pyramid", "--load-state", "state-fixed.bin"], "the scene is in the snapshot")]:
        r = run("run", *args, "--out", "x.csv", "--quiet")
        check(r.returncode == 2 and r.stderr.startswith("lockstep run: ") and r.stderr.count("\n") == 1 and says in r.stderr,
              "snapshots: run %s exits 2 with one line saying %r (got %d: %r)" % (" ".join(args), says, r.returncode, r.stderr))


snapshots()


def gpu_fixed():
    """Issue 33: `run --engine gpu-fixed` (the GPU engine's pipeline on Q16.16,
    here its host build) writes the fixed engine's hash on every frame, and
    compare accepts it beside the other engines."""
    for scene in ["drop", "pyramid", "bowl"]:
        a = run("run", scene, "--engine", "fixed", "--frames", "150", "--out", "gf-fixed-%s.csv" % scene, "--quiet")
        b = run("run", scene, "--engine", "gpu-fixed", "--frames", "150", "--out", "gf-gpu-%s.csv" % scene, "--quiet")
        check(a.returncode == 0 and b.returncode == 0, "gpu-fixed %s: both runs exit 0 (got %r %r)" % (scene, a.stderr, b.stderr))
        ha = open(os.path.join(WORK, "gf-fixed-%s.csv.hashes" % scene)).read()
        hb = open(os.path.join(WORK, "gf-gpu-%s.csv.hashes" % scene)).read() if b.returncode == 0 else ""
        check(ha == hb and ha.count("\n") == 151, "gpu-fixed %s: every frame's hash is the fixed engine's" % scene)
    c = run("compare", "stack5", "--engines", "fixed,gpu-fixed", "--frames", "120", "--no-report")
    check(c.returncode == 0 and "AGREE" in c.stdout, "compare fixed,gpu-fixed agrees (got %d: %r)" % (c.returncode, c.stdout[-300:]))


gpu_fixed()


def recordings():
    """Issue 32: `run --record` then `replay`: exit 0 and "no difference over
    N frames" on the recording's engine, exit 1 naming frame, body, field and
    stage on another number type, exit 1 naming the frame of a changed hash,
    exit 2 with one line for a bad recording or inputs file; the gpu engine's
    snapshots resume through the command line too."""
    with open(os.path.join(WORK, "kicks.json"), "w") as f:
        f.write('{"format": "lockstep-inputs", "version": 1, "inputs": [\n'
                '  {"frame": 10, "kind": "impulse", "id": 3, "impulse": [0, 4, 1], "point": [0.5, 1, 0]},\n'
                '  {"frame": 25, "kind": "set_velocity", "id": 1, "velocity": [1, 0, 0]}]}\n')
    r = run("run", "pyramid", "--frames", "60", "--inputs", "kicks.json", "--record", "p.rec.json", "--snapshot-every", "20",
            "--out", "p.csv", "--quiet")
    check(r.returncode == 0 and os.path.exists(os.path.join(WORK, "p.rec.json")), "run --record exits 0 (%r)" % r.stderr)
    rec = json.load(open(os.path.join(WORK, "p.rec.json")))
    check(rec["format"] == "lockstep-recording" and rec["engine"] == "fixed" and len(rec["hashes"]) == 60 and
          [s["frame"] for s in rec["snapshots"]] == [20, 40, 60] and len(rec["inputs"]) == 2,
          "the recording holds the engine, 60 hashes, snapshots at 20, 40, 60 and 2 inputs")
    hashes = open(os.path.join(WORK, "p.csv.hashes")).read().splitlines()[1:]
    check([h.split(",")[1] for h in hashes] == rec["hashes"], "the recording's hashes are the run's .hashes")
    r = run("replay", "p.rec.json", "--quiet")
    check(r.returncode == 0 and r.stdout.startswith("replay: no difference over 60 frames"), "replay on fixed: exit 0, no difference (got %d %r)" % (r.returncode, r.stdout))
    r = run("replay", "p.rec.json", "--engine", "double", "--quiet")
    check(r.returncode == 1 and "differ first at frame 1 " in r.stdout and "frame 1: body " in r.stdout and "stage: " in r.stdout
          and "different number types (fixed, double)" in r.stdout, "replay on double: exit 1, frame 1, body, stage, why (got %d %r)" % (r.returncode, r.stdout))
    rec["hashes"][33] = ("0" if rec["hashes"][33][0] != "0" else "1") + rec["hashes"][33][1:]
    json.dump(rec, open(os.path.join(WORK, "p-tampered.rec.json"), "w"))
    r = run("replay", "p-tampered.rec.json", "--quiet")
    check(r.returncode == 1 and "differ first at frame 34 " in r.stdout and "snapshot of frame 40" in r.stdout,
          "a changed hash: exit 1 naming frame 34, compared at the snapshot of frame 40 (got %d %r)" % (r.returncode, r.stdout))
    bad_inputs = os.path.join(WORK, "bad-inputs.json")
    with open(bad_inputs, "w") as f:
        f.write('{"format": "lockstep-inputs", "version": 1, "inputs": [{"frame": 5, "kind": "shove", "id": 1}]}')
    with open(os.path.join(WORK, "bad.rec.json"), "w") as f:
        f.write('{"format": "lockstep-recording", "version": 1, "engine": "fixed"}')
    for args, says in [(["replay", "missing.rec.json"], "cannot read"),
                       (["replay", "bad.rec.json"], "build: missing"),
                       (["replay", "p.csv"], "not valid JSON"),
                       (["run", "pyramid", "--inputs", "bad-inputs.json", "--out", "x.csv"], 'inputs[0].kind: "shove" is not an input kind'),
                       (["run", "pyramid", "--frames", "4", "--inputs", "kicks.json", "--out", "x.csv"], "inputs[0].frame: 10 is outside the run's frames [1, 4]"),
                       (["run", "--load-state", "missing.bin", "--record", "r.json"], "a recording starts at frame 0")]:
        r = run(*args)
        check(r.returncode == 2 and r.stderr.count("\n") == 1 and says in r.stderr,
              "%s exits 2 with one line saying %r (got %d: %r)" % (" ".join(args), says, r.returncode, r.stderr))
    # The gpu engine's snapshots through the command line: run to 2N = run to N + resume N.
    if "gpu" in run("--version").stdout:
        full = run("run", "bowl", "--engine", "gpu", "--frames", "40", "--out", "g-full.csv", "--quiet")
        first = run("run", "bowl", "--engine", "gpu", "--frames", "20", "--out", "g-first.csv", "--quiet", "--save-state", "g.bin")
        rest = run("run", "--load-state", "g.bin", "--frames", "20", "--out", "g-rest.csv", "--quiet")
        h_full = open(os.path.join(WORK, "g-full.csv.hashes")).read().splitlines()[1:]
        h_rest = open(os.path.join(WORK, "g-rest.csv.hashes")).read().splitlines()[1:] if rest.returncode == 0 else []
        check(full.returncode == 0 and first.returncode == 0 and rest.returncode == 0 and h_rest == h_full[20:],
              "gpu: run to 40 = run to 20 + resume 20 (got %r %r)" % (rest.stderr, h_rest[:1]))


recordings()

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("cli_test: all checks passed")
