#!/usr/bin/env python3
"""Tests of the Python port's verifier: a perturbed vector is rejected with
its tcId / frame named, and the port's rules hold on hand-checked values.

  python3 vectors/python/test_q16_port.py [DIR]      (DIR: default vectors/data)
"""

import copy
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import q16_port  # noqa: E402
import verify_vectors  # noqa: E402

DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")


def load(rel):
    with open(os.path.join(DIR, rel), encoding="utf-8") as f:
        return json.load(f)


class PortRules(unittest.TestCase):
    """Hand-checked values (docs/SPEC.md 0.3), independent of the vector files."""

    def test_nearest_ties_to_even_and_sign_symmetric(self):
        st = set()
        self.assertEqual(q16_port.mul(-1, 1, st), 0)          # -2^-16 ulp -> 0
        self.assertEqual(q16_port.mul(1, 0x8000, st), 0)      # 0.5 ulp: a tie, to even
        self.assertEqual(q16_port.mul(-1, 0x8000, st), 0)     # -0.5 ulp: to even
        self.assertEqual(q16_port.mul(3, 0x8000, st), 2)      # 1.5 ulp -> 2
        self.assertEqual(q16_port.mul(-3, 0x8000, st), -2)    # round(-x) = -round(x)
        self.assertEqual(q16_port.div(-65536, 3 * 65536, st), -21845)  # -1/3 to nearest
        self.assertEqual(q16_port.div(65536, 3 * 65536, st), 21845)
        self.assertEqual(q16_port.sqrt(131072, st), 92682)    # sqrt(2) = 1.41421..: 92681.9 -> 92682
        self.assertEqual(st, set())

    def test_ties_to_even(self):
        st = set()
        self.assertEqual(q16_port.from_double_bits("3ee0000000000000", st), 0)  # 2^-17 = 0.5 ulp -> 0
        self.assertEqual(q16_port.from_double_bits("3ef8000000000000", st), 2)  # 1.5 ulp -> 2
        self.assertEqual(q16_port.from_double_bits("bef8000000000000", st), -2)  # -1.5 ulp -> -2
        self.assertEqual(st, set())

    def test_saturation_raises_overflow(self):
        st = set()
        self.assertEqual(q16_port.add(q16_port.INT32_MAX, 1, st), q16_port.INT32_MAX)
        self.assertEqual(st, {"overflow"})

    def test_dt_and_gravity_constants(self):
        st = set()
        dt = q16_port.from_double_bits("3f91111111111111", st)  # 1/60
        self.assertEqual(dt, 1092)
        self.assertEqual(q16_port.from_double_bits("c0239eb851eb851f", st), -642908)  # -9.81
        self.assertEqual(st, set())


class VerifierRejectsPerturbed(unittest.TestCase):
    def test_arithmetic_output(self):
        doc = load("arithmetic.json")
        verify_vectors.verify_arithmetic(doc)  # the checked-in file passes
        bad = copy.deepcopy(doc)
        group = next(g for g in bad["testGroups"] if g["operation"] == "mul")
        t = group["tests"][10]
        t["out"]["r"] += 1
        with self.assertRaises(verify_vectors.Mismatch) as cm:
            verify_vectors.verify_arithmetic(bad)
        self.assertIn("tcId %d" % t["tcId"], str(cm.exception))
        self.assertIn("out.r expected", str(cm.exception))

    def test_arithmetic_status(self):
        bad = load("arithmetic.json")
        for g in bad["testGroups"]:
            for t in g["tests"]:
                if t["status"] == ["overflow"]:
                    t["status"] = []
                    with self.assertRaises(verify_vectors.Mismatch) as cm:
                        verify_vectors.verify_arithmetic(bad)
                    self.assertIn("tcId %d" % t["tcId"], str(cm.exception))
                    self.assertIn("status expected []", str(cm.exception))
                    return
        self.fail("no overflow case")

    def test_scene_state(self):
        doc = load("scenes/drop.json")
        verify_vectors.verify_scene_hashes(doc, "scenes/drop.json")
        bad = copy.deepcopy(doc)
        bad["states"][40]["bodies"][0][1] += 1  # frame 40, body 0, p.y
        with self.assertRaises(verify_vectors.Mismatch) as cm:
            verify_vectors.verify_scene_hashes(bad, "scenes/drop.json")
        self.assertIn("frame 40", str(cm.exception))

    def test_formula_hash(self):
        bad = load("formulas.json")
        for g in bad["testGroups"]:
            if g["function"] == "state_hash":
                g["tests"][0]["in"]["bodies"][0][13] ^= 1  # asleep flipped
                with self.assertRaises(verify_vectors.Mismatch) as cm:
                    verify_vectors.verify_formula_hashes(bad)
                self.assertIn("tcId %d" % g["tests"][0]["tcId"], str(cm.exception))
                return
        self.fail("no state_hash group")


if __name__ == "__main__":
    if len(sys.argv) > 1 and not sys.argv[1].startswith("-"):
        DIR = sys.argv.pop(1)
    unittest.main(verbosity=2)
