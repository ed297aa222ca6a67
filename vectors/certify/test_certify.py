#!/usr/bin/env python3
"""Test of certify.py's verdict: with a deliberately perturbed vector file it
exits 1 and names the first differing build, scene, frame, body and field,
while an unperturbed scene is certified. One native g++ -O0 build, two scenes;
the reference vectors are generated fresh by the lockstep command given.

  python3 vectors/certify/test_certify.py LOCKSTEP WORKDIR
"""

import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    lockstep, work = argv[1], os.path.abspath(argv[2])
    vec = os.path.join(work, "vectors")
    if os.path.exists(vec):
        shutil.rmtree(vec)
    subprocess.run([lockstep, "vectors", "generate", vec, "--scene", "drop", "--scene", "stack5", "--quiet"], check=True)
    # drop as a build that went wrong at frame 50 in body 0's p.y would see it.
    drop = json.load(open(os.path.join(vec, "scenes", "drop.json"), encoding="utf-8"))
    want = drop["states"][50]["bodies"][0][1]
    drop["states"][50]["bodies"][0][1] = want + 1
    for f in range(50, len(drop["hashes"])):
        drop["hashes"][f] = "%016x" % (int(drop["hashes"][f], 16) ^ 1)
    json.dump(drop, open(os.path.join(vec, "scenes", "drop.json"), "w", encoding="utf-8"))

    p = subprocess.run([sys.executable, os.path.join(HERE, "certify.py"), "--builds", "x86_64-gcc-O0", "--scenes",
                        "drop,stack5", "--vectors", vec, "--work", work, "--jobs", "1"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = p.stdout
    print(out)
    expected = ("first difference: build x86_64-gcc-O0, scene drop, frame 50, body 0, field p.y: expected %d "
                "(the vectors' stored state), got %d" % (want + 1, want))
    checks = [
        (p.returncode == 1, "exit status 1 (got %d)" % p.returncode),
        (expected in out, "the message names frame, body and field: " + expected),
        ("| DIFF@50 | all 600 |" in out, "the table shows drop DIFF@50 and stack5 certified"),
    ]
    failed = [m for ok, m in checks if not ok]
    for m in failed:
        print("FAILED: " + m, file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
