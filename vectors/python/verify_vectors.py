#!/usr/bin/env python3
"""Checks the independent Python port (q16_port.py) against the lockstep
test vectors, bit for bit, with the standard library only.

  python3 vectors/python/verify_vectors.py [DIR]     (DIR: default vectors/data)

Checks:
  1. arithmetic.json: every test of every Q16.16 operation: output and status.
  2. formulas.json, group state_hash: eq 92 from the given bodies.
  3. scenes/*.json: eq 92 recomputed from every stored full state equals the
     hash of that frame (so the state layout and the hash are enough to check
     a port frame by frame), and the file's counts are consistent.
Exit status 0 when everything agrees; 1 with the first difference named
(file, tcId or frame, field, expected, actual).
"""

import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import q16_port  # noqa: E402

SUPPORTED_SCHEMA = 1


class Mismatch(Exception):
    pass


def load(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def check_schema(doc, name):
    if doc.get("schemaVersion") != SUPPORTED_SCHEMA:
        raise Mismatch("%s: schemaVersion %r is not supported (this reader: %d)"
                       % (name, doc.get("schemaVersion"), SUPPORTED_SCHEMA))


def verify_arithmetic(doc, name="arithmetic.json"):
    """Returns the number of tests checked; raises Mismatch on the first difference."""
    check_schema(doc, name)
    count = 0
    for group in doc["testGroups"]:
        op = group["operation"]
        if op not in q16_port.OPERATIONS:
            raise Mismatch("%s: operation %r is not in the port" % (name, op))
        for t in group["tests"]:
            r, status = q16_port.compute(op, t["in"])
            count += 1
            if r != t["out"]["r"]:
                raise Mismatch("%s: tcId %d (%s, in %s): out.r expected %s, got %s"
                               % (name, t["tcId"], op, json.dumps(t["in"]), json.dumps(t["out"]["r"]), json.dumps(r)))
            if status != t["status"]:
                raise Mismatch("%s: tcId %d (%s, in %s): status expected %s, got %s"
                               % (name, t["tcId"], op, json.dumps(t["in"]), t["status"], status))
    if count != doc["numberOfTests"]:
        raise Mismatch("%s: numberOfTests is %d but the file holds %d tests" % (name, doc["numberOfTests"], count))
    return count


def verify_formula_hashes(doc, name="formulas.json"):
    check_schema(doc, name)
    count = 0
    for group in doc["testGroups"]:
        if group["function"] != "state_hash":
            continue
        for t in group["tests"]:
            got = q16_port.state_hash(t["in"]["bodies"])
            count += 1
            if got != t["out"]["hash"]:
                raise Mismatch("%s: tcId %d (state_hash): out.hash expected %s, got %s"
                               % (name, t["tcId"], t["out"]["hash"], got))
    if count == 0:
        raise Mismatch("%s: no state_hash group" % name)
    return count


def verify_scene_hashes(doc, name):
    check_schema(doc, name)
    hashes = doc["hashes"]
    if doc["error"] is None and len(hashes) != doc["frames"] + 1:
        raise Mismatch("%s: %d hashes for %d frames (expected frames + 1)" % (name, len(hashes), doc["frames"]))
    if doc["stateFields"][:14] != ["p.x", "p.y", "p.z", "q.w", "q.x", "q.y", "q.z",
                                   "v.x", "v.y", "v.z", "w.x", "w.y", "w.z", "asleep"]:
        raise Mismatch("%s: unexpected stateFields %s" % (name, doc["stateFields"]))
    stored = [s["frame"] for s in doc["states"]]
    if stored != doc["stateFrames"]:
        raise Mismatch("%s: states are stored at %s but stateFrames says %s" % (name, stored[:5], doc["stateFrames"][:5]))
    for s in doc["states"]:
        f = s["frame"]
        if len(s["bodies"]) != doc["bodyCount"]:
            raise Mismatch("%s: frame %d holds %d bodies, bodyCount is %d" % (name, f, len(s["bodies"]), doc["bodyCount"]))
        got = q16_port.state_hash(s["bodies"])
        if got != hashes[f]:
            raise Mismatch("%s: frame %d: eq 92 over the stored state gives %s, the file's hash is %s"
                           % (name, f, got, hashes[f]))
    return len(doc["states"])


def verify_directory(directory):
    """Returns a list of report lines; raises Mismatch on the first difference."""
    index = load(os.path.join(directory, "index.json"))
    check_schema(index, "index.json")
    lines = []
    for entry in index["files"]:
        path = entry["path"]
        doc = load(os.path.join(directory, path))
        if entry["level"] == 1:
            n = verify_arithmetic(doc, path)
            lines.append("ok   %s: %d tests, every output and status bit for bit" % (path, n))
        elif entry["level"] == 2:
            n = verify_formula_hashes(doc, path)
            lines.append("ok   %s: %d state_hash tests (eq 92)" % (path, n))
        elif entry["level"] == 3:
            n = verify_scene_hashes(doc, path)
            lines.append("ok   %s: eq 92 over %d stored states matches the frame hashes" % (path, n))
    return lines


def main(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    directory = argv[1] if len(argv) > 1 else os.path.join(here, "..", "data")
    try:
        for line in verify_directory(directory):
            print(line)
    except Mismatch as e:
        print("MISMATCH " + str(e), file=sys.stderr)
        return 1
    except (OSError, KeyError, ValueError) as e:
        print("ERROR reading the vectors in %s: %r" % (directory, e), file=sys.stderr)
        return 2
    print("python port: agrees with the vectors in %s" % directory)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
