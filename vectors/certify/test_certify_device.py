#!/usr/bin/env python3
"""Test of certify_device.py's verdict without a GPU: a stand-in for the
`lockstep` command writes the run record a device run writes. Its hashes equal
to the vectors' certify the scene ("all N"); one changed frame is named
(DIFF@7); a run that says it fell back to the host build is an error, never
a certified device row.

  python3 vectors/certify/test_certify_device.py VECTORS WORKDIR
"""

import json
import os
import stat
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import certify  # noqa: E402
import certify_device  # noqa: E402

FAKE = """#!/usr/bin/env python3
import json, sys
# lockstep run SCENE --engine gpu-fixed ... --out FILE, as a device run records it
args = sys.argv[1:]
scene, out = args[1], args[args.index("--out") + 1]
mode = open(%r).read().strip()
if mode == "host":
    print("lockstep run: scene '%%s' on gpu-fixed (host build: no CUDA device)" %% scene)
hashes = json.load(open(%r))[scene]
if mode == "diff":
    hashes[7] = "%%016x" %% (int(hashes[7], 16) ^ 1)
json.dump({"format": "lockstep-run", "hash": hashes}, open(out + ".run.json", "w"))
"""


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    vectors, work = argv[1], os.path.abspath(argv[2])
    os.makedirs(work, exist_ok=True)
    ref = certify.load_vectors(vectors)
    scenes = ["drop", "stack5"]
    mode_file, hashes_file = os.path.join(work, "mode"), os.path.join(work, "hashes.json")
    json.dump({s: ref[s]["hashes"] for s in scenes}, open(hashes_file, "w"))
    fake = os.path.join(work, "fake_lockstep")
    with open(fake, "w") as f:
        f.write(FAKE % (mode_file, hashes_file))
    os.chmod(fake, os.stat(fake).st_mode | stat.S_IEXEC)
    failures = []
    for mode, want in (("same", lambda c: c == ("ok", "all %d" % ref["drop"]["frames"])),
                       ("diff", lambda c: c == ("diff", "DIFF@7")),
                       ("host", lambda c: c[0] == "error" and "host build" in c[1])):
        open(mode_file, "w").write(mode)
        cells = certify_device.certify_device(fake, ref, scenes, os.path.join(work, mode))
        print(mode, cells)
        if not want(cells["drop"]):
            failures.append("%s: drop gave %r" % (mode, cells["drop"]))
    if failures:
        print("FAILED: " + "; ".join(failures))
        return 1
    print("certify_device: certifies equal hashes, names the first differing frame, refuses a host-build run")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
