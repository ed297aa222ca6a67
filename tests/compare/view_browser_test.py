#!/usr/bin/env python3
"""The replay page in a real browser (headless Chromium): `lockstep compare
bowl --report` and `lockstep view` pages load without console errors, draw one
box per body and run, the slider moves the scene (screenshot pixels differ
between frames), the divergence marker sits at the frame the harness reports,
and a selected body's panel shows its state and recorded contacts. What is
drawn: for a settled scene (all asleep), a scene with a static body and two
runs overlaid and side by side, each group of boxes (awake, asleep, static,
run 2) drawn alone (#only, #run) covers the pixels its boxes should cover and
nothing else; without WebGL the page shows a message and its charts.

Exit 77 (ctest: skipped, shown as such) when no Chromium is installed; CI
installs it (.ci/packages).

usage: view_browser_test.py LOCKSTEP WORKDIR
"""
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

LOCKSTEP, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
WIDTH, HEIGHT, SIDE, BOTTOM = 1280, 800, 400, 130  # window; the side panel and the controls below the 3D view
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def find_chromium():
    for name in ["chromium", "chromium-browser", "google-chrome", "google-chrome-stable"]:
        path = shutil.which(name)
        if path:
            return path
    return None


CHROMIUM = find_chromium()
if not CHROMIUM:
    print("SKIPPED: no chromium on PATH; the replay page's browser test needs it (apt-get install chromium; "
          "CI installs it through .ci/packages)")
    sys.exit(77)

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         "--hide-scrollbars", "--window-size=%d,%d" % (WIDTH, HEIGHT), "--virtual-time-budget=4000",
         "--enable-logging=stderr", "--v=0", "--user-data-dir=" + os.path.join(WORK, "chromium-profile")]


def chromium(*args, flags=None, allowed=None):
    p = subprocess.run([CHROMIUM, *(flags or FLAGS), *args], capture_output=True, text=True, timeout=180)
    uncaught = [l for l in p.stderr.splitlines() if "CONSOLE" in l and ("Uncaught" in l or "Error" in l) and
                not (allowed and allowed in l)]
    check(not uncaught, "no console errors in Chromium's log (got %s)" % uncaught[:3])
    return p


def status(url, flags=None, allowed=None):
    """The page's #lockstep-status after load: frame, boxes drawn, markers, errors."""
    p = chromium("--dump-dom", url, flags=flags, allowed=allowed)
    m = re.search(r'<pre id="lockstep-status"[^>]*>(.*?)</pre>', p.stdout, re.S)
    check(m is not None and m.group(1).strip(), "the page reports its status (%s; stderr %s)" % (url, p.stderr[-500:]))
    if not m or not m.group(1).strip():
        return {}, p.stdout
    return json.loads(m.group(1).replace("&quot;", '"').replace("&amp;", "&")), p.stdout


def png_pixels(path):
    """(width, height, rows of RGB(A) bytes) of an 8-bit, non-interlaced PNG."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and interlace == 0 and ctype in (2, 6), (depth, ctype, interlace)
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, bpp, rows


def view_region(path):
    """The 3D view's pixels (left of the side panel, above the controls), RGB."""
    w, h, bpp, rows = png_pixels(path)
    out = []
    for y in range(0, h - BOTTOM):
        r = rows[y]
        out.append(bytes(r[i] for x in range(0, w - SIDE) for i in range(x * bpp, x * bpp + 3)))
    return out


def differing(a, b):
    n = 0
    for ra, rb in zip(a, b):
        for i in range(0, len(ra), 3):
            if ra[i:i + 3] != rb[i:i + 3]:
                n += 1
    return n


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
# LOCKSTEP_VIEW_PAGE_JS=FILE: every page written is given FILE as its script
# instead of the built-in one (to run these checks against another version of
# compare/view/page.js, e.g. an older one, without rebuilding lockstep).
PAGE_JS = os.environ.get("LOCKSTEP_VIEW_PAGE_JS")


def swap_script(path):
    html = open(path, encoding="utf-8").read()
    start = html.rindex("<script>") + len("<script>")
    end = html.rindex("</script>")
    js = open(PAGE_JS, encoding="utf-8").read().replace("</", "<\\/")
    with open(path, "w", encoding="utf-8") as f:
        f.write(html[:start] + js + html[end:])


def run(*a):
    p = subprocess.run([LOCKSTEP, *a], capture_output=True, text=True, cwd=WORK, timeout=600)
    if PAGE_JS and a[0] in ("view", "compare"):
        for root, _, files in os.walk(WORK):
            for name in files:
                if name.endswith(".html") and os.path.getmtime(os.path.join(root, name)) >= START - 1:
                    swap_script(os.path.join(root, name))
    return p


import time
START = time.time()

# A comparison whose engines part: bowl (20 cubes poured into an SDF bowl), fixed against double.
cmp = run("compare", "bowl", "--engines", "fixed,double", "--frames", "120", "--report", "bowl", "--no-progress")
part = re.search(r"^fixed .* frame (\d+), body (\d+) ", cmp.stdout, re.M)
check(part is not None, "the harness reports where fixed parts from double (got %r)" % cmp.stdout[-600:])
parted = int(part.group(1)) if part else -1
page = "file://" + os.path.join(WORK, "bowl", "index.html")

st, dom = status(page + "#frame=0")
check(st.get("errors") == [], "bowl page: no errors (got %s)" % st.get("errors"))
check(st.get("boxes") == 20 * 2, "bowl page draws 20 boxes for each of 2 runs (got %s)" % st.get("boxes"))
markers = [m for m in st.get("markers", []) if m["kind"] == "parted"]
check([m["frame"] for m in markers] == [parted], "the divergence marker sits at the harness's frame %d (got %s)" % (parted, markers))
dom_marker = re.search(r'class="marker parted"[^>]*data-frame="(\d+)"', dom)
check(dom_marker is not None and int(dom_marker.group(1)) == parted, "the slider's marker element carries frame %d" % parted)

shots = {}
for f in [0, 100]:
    path = os.path.join(WORK, "bowl-%d.png" % f)
    chromium("--screenshot=" + path, page + "#frame=%d" % f)
    check(os.path.exists(path), "screenshot at frame %d" % f)
    if os.path.exists(path):
        shots[f] = view_region(path)
if len(shots) == 2:
    colours = {shots[0][y][x:x + 3] for y in range(0, len(shots[0]), 7) for x in range(0, len(shots[0][0]), 21)}
    check(len(colours) > 8, "the 3D view at frame 0 is drawn (%d colours sampled)" % len(colours))
    n = differing(shots[0], shots[100])
    print("pixels of the 3D view differing between frames 0 and 100: %d" % n)
    check(n > 2000, "the slider moves the scene: frames 0 and 100 differ in %d pixels (want > 2000)" % n)

# `lockstep view` of three runs of stack5 (two fixed, one float), contacts recorded on the first.
for name, engine, extra in [("a.csv", "fixed", ["--contacts"]), ("b.csv", "float", []), ("c.csv", "fixed", [])]:
    run("run", "stack5", "--engine", engine, "--frames", "60", "--out", name, "--no-progress", *extra)
v = run("view", "a.csv", "b.csv", "c.csv", "--out", "stack5.html")
check(v.returncode == 0, "lockstep view exits 0 (%s)" % v.stderr)
st, dom = status("file://" + os.path.join(WORK, "stack5.html") + "#frame=10&mode=side&select=0,2")
check(st.get("errors") == [], "stack5 page: no errors (got %s)" % st.get("errors"))
check(st.get("boxes") == 5 * 3, "stack5 page draws 5 boxes for each of 3 runs (got %s)" % st.get("boxes"))
check(st.get("frame") == 10, "#frame=10 opens frame 10 (got %s)" % st.get("frame"))
info = re.search(r'<div id="body-info">(.*?)</div>', dom, re.S)
text = info.group(1) if info else ""
check("a.csv, body 2 at frame 10" in text and "position" in text and "angular vel." in text,
      "the selected body's panel shows its state (got %r)" % text[:300])
check(re.search(r"contacts +\d+", text) is not None, "the panel lists the recorded contacts (got %r)" % text[-300:])
check("hashes of a.csv and c.csv are identical on all 61 frames" in dom, "the page names the two fixed runs' hash agreement")
# A click on the middle of the second column (side by side) picks a body of the second run; one on the sky none.
for pick, want in [("0.5,0.55", "b.csv, body "), ("0.5,0.02", "Click a body")]:
    st, dom = status("file://" + os.path.join(WORK, "stack5.html") + "#frame=10&mode=side&pick=" + pick)
    info = re.search(r'<div id="body-info">(.*?)</div>', dom, re.S)
    check(info is not None and info.group(1).startswith(want), "#pick=%s shows %r (got %r)" % (pick, want, info and info.group(1)[:60]))

# Playback: with #play the page advances on its own (virtual time in headless Chromium).
st, _ = status(page + "#frame=0&play")
check(st.get("frame", 0) > 0, "#play advances the frame (got %s)" % st.get("frame"))

# 10,000 bodies (a written CSV and run record of 3 frames, no engine run): one instanced box each.
n, frames = 10000, 3
bodies = [{"half_extents": [0.2, 0.2, 0.2], "position": [0.6 * (i % 100), 1.0, 0.6 * (i // 100)]} for i in range(n)]
scene = {"format": "lockstep-scene", "version": 1, "name": "grid10k", "frames": frames, "bodies": bodies}
with open(os.path.join(WORK, "grid.json"), "w") as f:
    json.dump(scene, f)
g = run("run", "grid.json", "--frames", "0", "--out", "grid.csv", "--no-progress")  # the run record's scene, as lockstep writes it
record = json.load(open(os.path.join(WORK, "grid.csv.run.json")))
record.update(frames_run=frames, hash=[], energy=[], asleep=[])
with open(os.path.join(WORK, "grid.csv.run.json"), "w") as f:
    json.dump(record, f)
with open(os.path.join(WORK, "grid.csv"), "w") as f:
    f.write("frame,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,asleep\n")
    for fr in range(frames + 1):
        for i, b in enumerate(bodies):
            p = b["position"]
            f.write("%d,%d,%g,%g,%g,1,0,0,0,0,0,0,0,0,0,%d\n" % (fr, i, p[0], p[1] - 0.1 * fr, p[2], fr == frames))
v = run("view", "grid.csv", "--out", "grid.html")
check(v.returncode == 0, "view of 10,000 bodies (%s)" % v.stderr)
st, _ = status("file://" + os.path.join(WORK, "grid.html") + "#frame=2&bench=20")
check(st.get("errors") == [] and st.get("boxes") == n, "10,000 bodies: no errors, 10,000 boxes (got %s, %s)" %
      (st.get("errors"), st.get("boxes")))
print("10,000 bodies: %s" % json.dumps(st.get("bench")))

# ---- What is drawn: each group of boxes rendered alone covers its boxes' pixels --
# #only=GROUP (awake, asleep, static) and #run=R draw one group of boxes on the
# bare background; the page's status gives each drawn box's eight corners
# projected to the canvas (camera math alone, not the drawing). In the
# screenshot, the inside of every box's outline must be drawn, and the canvas
# away from every outline must be background.
BACKGROUND = (0x1d, 0x1f, 0x24)


def hull(points):
    pts = sorted(set(map(tuple, points)))
    if len(pts) < 3:
        return pts
    cross = lambda o, a, b: (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def scaled(poly, factor, grow=0.0):
    cx = sum(p[0] for p in poly) / len(poly)
    cy = sum(p[1] for p in poly) / len(poly)
    out = []
    for x, y in poly:
        dx, dy = x - cx, y - cy
        d = max(1e-9, (dx * dx + dy * dy) ** 0.5)
        out.append((cx + dx * factor + grow * dx / d, cy + dy * factor + grow * dy / d))
    return out


def inside(poly, x, y):
    # counter-clockwise convex polygon (hull's order)
    n = len(poly)
    for i in range(n):
        ax, ay = poly[i]
        bx, by = poly[(i + 1) % n]
        if (bx - ax) * (y - ay) - (by - ay) * (x - ax) < 0:
            return False
    return n >= 3


def drawn_check(what, url, want_boxes=None, min_boxes=1):
    """Screenshot of `url` (with #only/#run) against the boxes' outlines in its status."""
    st, _ = status(url)
    fp = st.get("footprints")
    check(st.get("errors") == [] and st.get("webgl") is True, "%s: no errors, WebGL on (got %s)" % (what, st.get("errors")))
    check(fp is not None, "%s: the page gives the drawn boxes' outlines (#only/#run)" % what)
    if not fp:
        return None
    boxes = fp["boxes"]
    if want_boxes is not None:
        check(len(boxes) == want_boxes, "%s: %d boxes in the group (got %d)" % (what, want_boxes, len(boxes)))
    left, top, cw, ch = [int(round(v)) for v in fp["canvas"]]
    path = os.path.join(WORK, re.sub(r"[^a-z0-9]+", "-", what.lower()).strip("-") + ".png")
    chromium("--screenshot=" + path, url)
    check(os.path.exists(path), "%s: screenshot" % what)
    if not os.path.exists(path):
        return None
    w, h, bpp, rows = png_pixels(path)

    def drawn(x, y):
        X, Y = left + x, top + y
        if not (0 <= X < w and 0 <= Y < h):
            return None
        i = X * bpp
        px = rows[Y][i:i + 3]
        return max(abs(px[c] - BACKGROUND[c]) for c in range(3)) > 6

    hulls = [hull(b["corners"]) for b in boxes]
    covered_boxes, worst = 0, 1.0
    for b, poly in zip(boxes, hulls):
        inner = scaled(poly, 0.7)
        xs, ys = [p[0] for p in inner], [p[1] for p in inner]
        n = hit = 0
        for y in range(max(0, int(min(ys))), min(ch, int(max(ys)) + 1), 2):
            for x in range(max(0, int(min(xs))), min(cw, int(max(xs)) + 1), 2):
                if inside(inner, x + 0.5, y + 0.5):
                    d = drawn(x, y)
                    if d is not None:
                        n += 1
                        hit += d
        if n:
            frac = hit / n
            worst = min(worst, frac)
            covered_boxes += frac >= 0.9
        else:
            covered_boxes += 1  # off screen or sub-pixel
    check(covered_boxes == len(boxes),
          "%s: every box of the group is drawn over its outline (%d of %d boxes covered >= 90%%; worst %.0f%%)" %
          (what, covered_boxes, len(boxes), 100 * worst))
    outer = [scaled(poly, 1.15, 3.0) for poly in hulls]
    n = stray = 0
    for y in range(0, ch, 3):
        for x in range(0, cw, 3):
            if any(inside(p, x + 0.5, y + 0.5) for p in outer):
                continue
            d = drawn(x, y)
            if d is not None:
                n += 1
                stray += d
    check(n == 0 or stray <= 0.002 * n, "%s: nothing drawn away from the group's boxes (%d of %d sampled pixels drawn)" %
          (what, stray, n))
    print("%s: %d boxes, worst coverage %.0f%%, %d stray pixels of %d" % (what, len(boxes), 100 * worst, stray, n))
    return st


# A settled stack: stack5 on fixed and on float, every cube asleep at frame 200.
for name, engine in [("s5-fixed.csv", "fixed"), ("s5-float.csv", "float")]:
    r = run("run", "stack5", "--engine", engine, "--frames", "200", "--out", name, "--no-progress")
    check(r.returncode == 0, "run stack5 on %s (%s)" % (engine, r.stderr))
run("view", "s5-fixed.csv", "--out", "s5-one.html")
run("view", "s5-fixed.csv", "s5-float.csv", "--out", "s5-two.html")
one = "file://" + os.path.join(WORK, "s5-one.html")
two = "file://" + os.path.join(WORK, "s5-two.html")
drawn_check("stack5 settled asleep", one + "#frame=200&only=asleep", want_boxes=5)
drawn_check("stack5 settled awake", one + "#frame=200&only=awake", want_boxes=0)
drawn_check("stack5 awake at frame 0", one + "#frame=0&only=awake", want_boxes=5)
# Two runs overlaid and side by side: each run alone, its boxes asleep.
for mode in ["", "&mode=side"]:
    for r in [0, 1]:
        drawn_check("stack5 two runs%s run %d" % (mode.replace("&mode=", " "), r),
                    two + "#frame=200&run=%d%s" % (r, mode), want_boxes=5)
    drawn_check("stack5 two runs%s run 1 asleep" % mode.replace("&mode=", " "), two + "#frame=200&run=1&only=asleep" + mode,
                want_boxes=5)
# Every box of both runs (no group hidden) in the screenshot of the whole page.
st, _ = status(two + "#frame=200&mode=side")
check(st.get("drawn", {}).get("0:asleep") == 5 and st.get("drawn", {}).get("1:asleep") == 5,
      "stack5 two runs: 5 asleep boxes in each run's asleep mesh (got %s)" % st.get("drawn"))

# A static body: a slab tilted 10 degrees, a cube resting on it (asleep at the end): tests/compare/data/ramp.json.
shutil.copy(os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "ramp.json"), os.path.join(WORK, "ramp.json"))
r = run("run", "ramp.json", "--out", "ramp.csv", "--no-progress")
check(r.returncode == 0, "run ramp.json (%s)" % r.stderr)
rv = run("view", "ramp.csv", "--out", "ramp.html")
check(rv.returncode == 0, "view ramp.csv (%s)" % rv.stderr)
ramp_page = "file://" + os.path.join(WORK, "ramp.html")
drawn_check("ramp static slab", ramp_page + "#frame=240&only=static", want_boxes=1)
drawn_check("ramp cube asleep", ramp_page + "#frame=240&only=asleep", want_boxes=1)
drawn_check("ramp cube awake", ramp_page + "#frame=1&only=awake", want_boxes=1)

# Without WebGL: a message in place of the 3D view; the charts and the panel still work.
no_gl = [f for f in FLAGS if "angle" not in f and "swiftshader" not in f] + ["--disable-webgl", "--disable-3d-apis"]
st, dom = status(two + "#frame=100&select=0,2", flags=no_gl, allowed="Error creating WebGL context")
check(st.get("webgl") is False and st.get("errors") == [], "without WebGL: status webgl false, no errors (got %s, %s)" %
      (st.get("webgl"), st.get("errors")))
check('id="no-webgl"' in dom and "needs WebGL" in dom, "without WebGL: the 3D view says so")
check("s5-fixed.csv, body 2 at frame 100" in dom, "without WebGL: the body panel works")
check(dom.count("<canvas") >= 3, "without WebGL: the charts are drawn (%d canvases)" % dom.count("<canvas"))

# Hashes are compared between runs of one engine only: float's is not marked.
st, dom = status(two + "#frame=50")
hashes = re.search(r'<div id="hashes">(.*?)</div>', dom, re.S)
check(hashes is not None and "differs" not in hashes.group(1), "fixed and float hashes are not compared (got %r)" %
      (hashes and hashes.group(1)[:300]))
check(st.get("tolerance", {}) and st["tolerance"].get("position") == 0.05 and "trajectory tolerance" in dom,
      "the page names the trajectory tolerance it judges against (got %s)" % st.get("tolerance"))

# A recording (issue 32): replayed on its own engine the page shows no
# overlay; on double it shows "DIVERGED at frame 1" from frame 1 on; the
# inputs' frames are marked on the slider.
with open(os.path.join(WORK, "kicks.json"), "w") as f:
    f.write('{"format": "lockstep-inputs", "version": 1, "inputs": [{"frame": 12, "kind": "set_velocity", "id": 2, '
            '"velocity": [2, 1, 0]}, {"frame": 30, "kind": "wake", "id": 0}]}')
r = run("run", "stack5", "--frames", "60", "--inputs", "kicks.json", "--record", "s5.rec.json", "--quiet", "--out", "s5r.csv")
check(r.returncode == 0, "run --record (%s)" % r.stderr)
for engine, diverged in [("fixed", -1), ("double", 1)]:
    rv = run("view", "s5.rec.json", "--engine", engine, "--out", "rec-%s.html" % engine)
    check(rv.returncode == 0, "view s5.rec.json --engine %s (%s)" % (engine, rv.stderr))
    url = "file://" + os.path.join(WORK, "rec-%s.html" % engine)
    st, dom = status(url + "#frame=20")
    rec = st.get("recording") or {}
    check(st.get("errors") == [] and st.get("boxes") == 5, "recording page on %s: 5 boxes, no errors (got %s, %s)" %
          (engine, st.get("boxes"), st.get("errors")))
    check(rec.get("inputs") == 2 and [m["frame"] for m in st.get("markers", []) if m["kind"] == "input"] == [12, 30],
          "recording page on %s: the inputs' frames 12 and 30 are marked (got %s)" % (engine, st.get("markers")))
    check(rec.get("diverged_frame") == diverged and rec.get("overlay") == (diverged >= 0),
          "recording page on %s: diverged at %d, overlay %s (got %s)" % (engine, diverged, diverged >= 0, rec))
    if diverged >= 0:
        check(re.search(r'<div id="diverged">DIVERGED at frame 1</div>', dom) is not None,
              "recording page on double: the overlay says DIVERGED at frame 1")
        st0, _ = status(url + "#frame=0")
        check((st0.get("recording") or {}).get("overlay") is False, "recording page on double: no overlay at frame 0")

# A recording that creates a body at frame 20 and removes body 1 at frame 40:
# 5 boxes, then 6, then 5 (a body is drawn only in the frames it exists).
with open(os.path.join(WORK, "create-destroy.json"), "w") as f:
    f.write('{"format": "lockstep-inputs", "version": 1, "inputs": [{"frame": 20, "kind": "create", "body": '
            '{"half_extents": [0.25, 0.5, 0.25], "mass": 0.75, "position": [0.5, 5, 0]}}, '
            '{"frame": 40, "kind": "destroy", "id": 1}]}')
r = run("run", "stack5", "--frames", "60", "--inputs", "create-destroy.json", "--record", "cd.rec.json", "--quiet",
        "--out", "cd.csv")
check(r.returncode == 0, "run --record with a creation and a removal (%s)" % r.stderr)
rv = run("view", "cd.rec.json", "--out", "rec-cd.html")
check(rv.returncode == 0 and "6 bodies" in rv.stdout, "view of a recording with a creation and a removal (%s %s)" % (rv.stdout, rv.stderr))
for f, boxes in [(10, 5), (30, 6), (50, 5)]:
    st, _ = status("file://" + os.path.join(WORK, "rec-cd.html") + "#frame=%d" % f)
    check(st.get("errors") == [] and st.get("boxes") == boxes,
          "recording with a creation and a removal: %d boxes at frame %d (got %s, %s)" % (boxes, f, st.get("boxes"), st.get("errors")))

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("view_browser_test: all checks passed")
