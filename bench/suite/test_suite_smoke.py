#!/usr/bin/python3
"""End-to-end smoke test of the suite machinery (ctest: suite_smoke): one short row in the
published bag layout (rgbdi-sim --bag, the suite's VINS yaml, rawlog-convert, rgbdi-slam --gt),
then the same row again from the cache, report and a paired comparison of the two labels.

  test_suite_smoke.py BUILD_DIR WORK_DIR
"""
import json
import os
import shutil
import subprocess
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
BUILD, WORK = (os.path.abspath(a) for a in sys.argv[1:3]) if len(sys.argv) >= 3 else (None, None)
ROW = "^handheld_s1_15hz_bag$"


def suite(*args):
    env = dict(os.environ, SUITE_OUT=WORK)
    return subprocess.run(["/usr/bin/python3", os.path.join(HERE, "suite.py"), *args],
                          env=env, capture_output=True, text=True)


class Smoke(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        cls.first = suite("run", "--tier", "quick", "--label", "a", "--build", BUILD,
                          "--sim-build", BUILD, "--only", ROW, "--duration", "8")
        cls.second = suite("run", "--tier", "quick", "--label", "b", "--build", BUILD,
                           "--sim-build", BUILD, "--only", ROW, "--duration", "8")

    def load(self, label):
        with open(os.path.join(WORK, "runs", label, "results.json")) as f:
            return json.load(f)

    def test_run_generates_then_reuses_the_sequence(self):
        self.assertEqual(self.first.returncode, 0, self.first.stdout + self.first.stderr)
        self.assertEqual(self.second.returncode, 0, self.second.stdout + self.second.stderr)
        a, b = self.load("a"), self.load("b")
        self.assertEqual(a["header"]["generated"], 1)
        self.assertEqual(b["header"]["generated"], 0)  # cached
        [r] = a["results"]
        self.assertEqual(r["status"], "ok")
        self.assertEqual(r["sequence"], b["results"][0]["sequence"])
        # 8 s of hand-held motion at 15 Hz through the bag layout: tracked all along
        self.assertEqual(r["frames"], 121)
        self.assertLess(r["ate_final"], 0.05)
        self.assertLess(r["ate_odometry"], 0.05)
        self.assertGreater(r["coverage"], 0.5)
        self.assertGreater(r["cpu_s"], 0.0)
        self.assertGreater(r["peak_rss_mb"], 10.0)
        entry = r["sequence"]
        with open(os.path.join(entry, "generation.json")) as f:
            g = json.load(f)
        self.assertIn("rawlog-convert", g["steps"])
        self.assertFalse(os.path.exists(os.path.join(entry, "sim")))  # the bag is not kept
        self.assertIn("| handheld 15hz_bag | 1 | 0 |", self.first.stdout)
        with open(os.path.join(WORK, "runs", "a", "results.csv")) as f:
            self.assertTrue(f.readline().startswith("id,condition,status,ate_odometry"))

    def test_compare_of_two_runs_of_one_build(self):
        c = suite("compare", "a", "b")
        self.assertEqual(c.returncode, 0, c.stderr)
        # one pair; the ATE of a run is not bitwise repeatable across runs (threads), but within
        # 5 % on this row, so the verdict is "no clear change"
        self.assertIn("1 sequences in both.", c.stdout)
        self.assertIn("verdict: no clear change", c.stdout)
        self.assertTrue(os.path.isfile(os.path.join(WORK, "runs", "compare_a_b.md")))

    def test_bad_label_is_refused(self):
        c = suite("compare", "a", "no_such_label")
        self.assertNotEqual(c.returncode, 0)
        self.assertIn("no_such_label/results.json", c.stderr)


if __name__ == "__main__":
    if BUILD is None:
        sys.exit("usage: test_suite_smoke.py BUILD_DIR WORK_DIR")
    unittest.main(argv=sys.argv[:1])
