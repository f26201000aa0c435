#!/usr/bin/python3
"""Unit tests of the benchmark suite's machinery (ctest: suite_unit). Known answers only."""
import math
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import suite_journal  # noqa: E402
import suite_rows  # noqa: E402
import suite_run  # noqa: E402
import suite_stats  # noqa: E402
from suite_cache import entry_key, prune_cache, row_config_text, sim_arguments  # noqa: E402

DEFINITION = suite_rows.load_definition(os.path.join(HERE, "suite.json"))
RULES = DEFINITION["compare"]


class Statistics(unittest.TestCase):
    def test_median_odd_and_even(self):
        self.assertEqual(suite_stats.median([3.0, 1.0, 2.0]), 2.0)
        self.assertEqual(suite_stats.median([4.0, 1.0, 3.0, 2.0]), 2.5)
        self.assertRaises(ValueError, suite_stats.median, [])

    def test_percentile_interpolates_linearly(self):
        v = [10.0, 20.0, 30.0, 40.0, 50.0]
        self.assertEqual(suite_stats.percentile(v, 0), 10.0)
        self.assertEqual(suite_stats.percentile(v, 100), 50.0)
        self.assertAlmostEqual(suite_stats.percentile(v, 90), 46.0)  # pos 3.6
        self.assertAlmostEqual(suite_stats.percentile(v, 10), 14.0)  # pos 0.4
        self.assertEqual(suite_stats.percentile([7.0], 90), 7.0)
        self.assertAlmostEqual(suite_stats.percentile(list(range(1, 11)), 90), 9.1)
        self.assertRaises(ValueError, suite_stats.percentile, v, 101)

    def test_spread_worst_direction(self):
        s = suite_stats.spread([0.1, 0.3, 0.2, None, float("nan")], "ate_final")
        self.assertEqual(s["n"], 3)
        self.assertEqual(s["median"], 0.2)
        self.assertAlmostEqual(s["p90"], 0.28)
        self.assertEqual(s["worst"], 0.3)
        c = suite_stats.spread([0.9, 1.0, 0.5], "coverage")
        self.assertEqual(c["worst"], 0.5)
        self.assertAlmostEqual(c["p90"], 0.58)  # the 10th percentile: 0.5 + 0.2 * 0.4
        self.assertIsNone(suite_stats.spread([None], "ate_final"))

    def test_summarise_counts_failures_and_excludes_them(self):
        results = [
            {"id": "a", "condition": "c1", "status": "ok", "ate_final": 0.1},
            {"id": "b", "condition": "c1", "status": "never initialised", "ate_final": 9.0},
            {"id": "c", "condition": "c1", "status": "ok", "ate_final": 0.3},
            {"id": "d", "condition": "c2", "status": "rgbdi-slam exit 1"},
        ]
        s = suite_stats.summarise(results, ["ate_final"])
        self.assertEqual(list(s), ["c1", "c2"])
        self.assertEqual(s["c1"]["runs"], 3)
        self.assertEqual(s["c1"]["failed"], ["b"])
        self.assertEqual(s["c1"]["ate_final"]["median"], 0.2)
        self.assertEqual(s["c1"]["ate_final"]["worst"], 0.3)
        self.assertEqual(s["c2"]["failed"], ["d"])
        self.assertIsNone(s["c2"]["ate_final"])


def run(rid, cond, status="ok", **m):
    return dict(id=rid, condition=cond, status=status, **m)


class PairedComparison(unittest.TestCase):
    def test_ratios_per_sequence(self):
        old = [run("a", "c", ate_final=0.10, cpu_s=10.0), run("b", "c", ate_final=0.20),
               run("x", "c", ate_final=0.1)]
        new = [run("a", "c", ate_final=0.12, cpu_s=9.0), run("b", "c", "never initialised"),
               run("y", "c", ate_final=0.1)]
        pairs, only_old, only_new = suite_stats.pair_runs(old, new, ["ate_final", "cpu_s"])
        self.assertEqual([p["id"] for p in pairs], ["a", "b"])
        self.assertAlmostEqual(pairs[0]["ratios"]["ate_final"], 1.2)
        self.assertAlmostEqual(pairs[0]["ratios"]["cpu_s"], 0.9)
        self.assertIsNone(pairs[1]["ratios"]["ate_final"])
        self.assertEqual((only_old, only_new), (["x"], ["y"]))
        self.assertIsNone(suite_stats.ratio(1.0, 0.0))
        self.assertIsNone(suite_stats.ratio(None, 1.0))

    def _pairs(self, ratios, metric="ate_final"):
        return [{"id": f"s{i}", "condition": "c", "old_status": "ok", "new_status": "ok",
                 "ratios": {metric: r, "cpu_s": 1.0}} for i, r in enumerate(ratios)]

    def test_summary_counts_worse_and_much_worse(self):
        s = suite_stats.ratio_summary(self._pairs([0.9, 1.0, 1.06, 1.1, 1.3]),
                                      ["ate_final"], 1.05, 1.20)
        m = s["metrics"]["ate_final"]
        self.assertEqual((m["n"], m["median"], m["worst"], m["worse"], m["much_worse"]),
                         (5, 1.06, 1.3, 3, 1))

    def test_verdict_worse_by_median(self):
        s = suite_stats.ratio_summary(self._pairs([1.06, 1.07, 1.08]), ["ate_final", "cpu_s"],
                                      1.05, 1.2)
        v = suite_stats.verdict(s, ["ate_final"], "cpu_s", RULES)
        self.assertTrue(v.startswith("verdict: worse (ate_final median ratio 1.070 > 1.05)"), v)
        self.assertTrue(v.endswith("CPU median ratio 1.000"), v)

    def test_verdict_worse_by_many_much_worse_sequences(self):
        # median 1.0 but 2 of 10 sequences above x1.2: more than 10 %
        s = suite_stats.ratio_summary(self._pairs([1.0] * 8 + [1.5, 1.6]), ["ate_final"],
                                      1.05, 1.2)
        v = suite_stats.verdict(s, ["ate_final"], "cpu_s", RULES)
        self.assertIn("verdict: worse", v)
        self.assertIn("2 of 10 sequences worse than x1.20", v)
        # one of ten is allowed
        s = suite_stats.ratio_summary(self._pairs([1.0] * 9 + [1.5]), ["ate_final"], 1.05, 1.2)
        self.assertIn("verdict: no clear change",
                      suite_stats.verdict(s, ["ate_final"], "cpu_s", RULES))

    def test_verdict_better_and_failures(self):
        s = suite_stats.ratio_summary(self._pairs([0.8, 0.9, 0.94]), ["ate_final"], 1.05, 1.2)
        self.assertIn("verdict: better (ate_final median ratio 0.900 < 0.95)",
                      suite_stats.verdict(s, ["ate_final"], "cpu_s", RULES))
        p = self._pairs([0.8, 0.9, 0.94])
        p[0]["new_status"] = "never initialised"
        s = suite_stats.ratio_summary(p, ["ate_final"], 1.05, 1.2)
        self.assertEqual(s["new_failures"], ["s0"])
        self.assertIn("verdict: worse (1 runs newly fail, 0 fixed",
                      suite_stats.verdict(s, ["ate_final"], "cpu_s", RULES))


class ParameterDraw(unittest.TestCase):
    def test_deterministic_and_within_ranges(self):
        d = DEFINITION["draw"]
        presets = set()
        for profile in suite_rows.PROFILES:
            default = DEFINITION["profiles"][profile].get("speed_m_s")
            for seed in range(1, 60):
                k1, p1 = suite_rows.draw_sim_keys(DEFINITION, profile, seed, profile)
                k2, p2 = suite_rows.draw_sim_keys(DEFINITION, profile, seed, profile)
                self.assertEqual((k1, p1), (k2, p2))
                for key in suite_rows.WORLD_KEYS:
                    self.assertGreaterEqual(k1[key], d[key]["min"], key)
                    self.assertLessEqual(k1[key], d[key]["max"], key)
                self.assertIsInstance(k1["world_seed"], int)
                self.assertGreaterEqual(k1["world_seed"], 1)
                if profile == "wheeled_slopes":
                    self.assertNotIn("speed_m_s", k1)
                    presets.add(p1)
                else:
                    self.assertIsNone(p1)
                    self.assertGreaterEqual(k1["speed_m_s"], 0.6 * default - 1e-9)
                    self.assertLessEqual(k1["speed_m_s"], 1.4 * default + 1e-9)
                fast, _ = suite_rows.draw_sim_keys(DEFINITION, "handheld_fast", seed, "handheld",
                                                   fast=True)
                self.assertGreaterEqual(fast["speed_m_s"], d["speed_m_s_fast"]["min"])
                self.assertLessEqual(fast["speed_m_s"], d["speed_m_s_fast"]["max"])
        self.assertEqual(presets, {"slow", "normal", "fast"})

    def test_known_draw(self):
        # SHA-256("handheld:1:world_seed") starts with 7e9a24c8b5b7b: u = 0x7e9a24c8b5b7b / 16^13
        u = suite_rows.unit_draw("handheld", 1, "world_seed")
        self.assertAlmostEqual(u, 0.49454, places=5)
        self.assertEqual(suite_rows.draw_value({"int": True, "min": 1, "max": 10}, 0.0), 1)
        self.assertEqual(suite_rows.draw_value({"int": True, "min": 1, "max": 10}, 0.9999), 10)
        self.assertEqual(suite_rows.draw_value({"min": 2.0, "max": 4.0}, 0.25), 2.5)

    def test_seeds_differ_and_rates_share_the_world(self):
        rows = suite_rows.tier_rows(DEFINITION, "quick", "/repo")
        by_id = {r["id"]: r for r in rows}
        a, b = by_id["handheld_s1_15hz_bag"], by_id["handheld_s1_30hz_files"]
        self.assertEqual(a["sim_keys"], b["sim_keys"])
        self.assertNotEqual(a["sim_keys"], by_id["handheld_s2_15hz_bag"]["sim_keys"])
        self.assertEqual((a["fps"], a["layout"], b["fps"], b["layout"]),
                         (15, "bag", 30, "files"))
        # durations per rate; the full tier takes each profile's own length
        self.assertEqual((a["duration_s"], b["duration_s"]), (30, 20))
        full = suite_rows.tier_rows(DEFINITION, "full", "/repo")
        self.assertIsNone([r for r in full if r["id"] == "wheeled_circle_s6_30hz_files"][0]
                          ["duration_s"])
        # the images stay beside a files-layout rawlog; the other layouts embed them
        self.assertNotIn("--embedded-images", sim_arguments(b, "R.ini"))
        self.assertIn("--embedded-images", sim_arguments(a, "R.ini"))
        self.assertNotIn("--duration", sim_arguments(
            [r for r in full if r["id"] == "handheld_s1_15hz_bag"][0], "R.ini"))
        for p in suite_rows.PROFILES:
            self.assertEqual(sum(1 for r in rows if r["condition"] == f"{p} 15hz_bag"), 5)
        hard = [r for r in rows if r["id"].startswith("hard_black_handheld")][0]
        self.assertEqual(hard["extra_args"], ["--blackout", "11:2:black"])
        self.assertEqual(suite_rows.hard_args({"spin_turns": 1, "duration_s": 2}, 5),
                         ["--spin", "5:2:1"])
        self.assertEqual(suite_rows.hard_args({"time_offset_s": 0.02}, 5),
                         ["--time-offset", "0.02"])
        rec = [r for r in rows if r["recording"]][0]
        self.assertEqual(rec["recording"], "/shared/data/euroc_v102")
        self.assertIsNone(rec["duration_s"])

    def test_planned_duration_is_the_profiles_own_length(self):
        # the plan's frame count: rows of the profile's own length (duration_s None) count their
        # default duration (doc/simulator.md's table), not 0
        full = {r["id"]: r for r in suite_rows.tier_rows(DEFINITION, "full", "/repo")}
        plan = suite_rows.planned_duration_s
        self.assertEqual(plan(DEFINITION, full["handheld_s1_15hz_bag"]), 40)
        self.assertEqual(plan(DEFINITION, full["handheld_fast_s1_15hz_bag"]), 40)
        self.assertEqual(plan(DEFINITION, full["tracked_slopes_s2_30hz_files"]), 65)
        slopes = full["wheeled_slopes_s1_15hz_bag"]
        self.assertEqual(plan(DEFINITION, slopes),
                         {"slow": 148, "normal": 74, "fast": 99}[slopes["speed_preset"]])
        circle = dict(full["wheeled_circle_s1_15hz_bag"], sim_keys={"speed_m_s": 0.4})
        self.assertAlmostEqual(plan(DEFINITION, circle), 99.75, places=2)  # 3 laps at 0.4 m/s
        self.assertEqual(plan(DEFINITION, full["hard_black_handheld_s1_15hz_bag"]), 24)
        self.assertIsNone(plan(DEFINITION, [r for r in full.values() if r["recording"]][0]))


class SuiteFile(unittest.TestCase):
    def check_refused(self, edit, message):
        import copy
        import json
        d = copy.deepcopy(DEFINITION)
        edit(d)
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
            json.dump(d, f)
        try:
            with self.assertRaises(ValueError) as e:
                suite_rows.load_definition(f.name)
            self.assertIn(f.name + ": " + message, str(e.exception))
        finally:
            os.unlink(f.name)

    def test_errors_name_the_file_and_the_entry(self):
        self.check_refused(lambda d: d["tiers"]["quick"]["rates"].append("60hz"),
                           "tiers.quick: unknown rate '60hz'")
        self.check_refused(lambda d: d["draw"]["room_margin_m"].update(min=5),
                           "draw.room_margin_m: needs numbers min <= max")
        self.check_refused(lambda d: d["tiers"]["full"]["hard"]["profiles"].append("boat"),
                           "tiers.full.hard.profiles: unknown profile 'boat'")
        self.check_refused(lambda d: d.pop("compare"), "compare: missing")
        self.assertRaises(ValueError, suite_rows.load_definition, "/nonexistent/suite.json")


class Sequences(unittest.TestCase):
    def test_config_text_keeps_only_accepted_keys(self):
        row = suite_rows.tier_rows(DEFINITION, "quick", "/repo")[0]
        text, dropped = row_config_text(row, ["speed_m_s", "world_seed"])
        self.assertIn("[sim]\n", text)
        self.assertIn(f"world_seed = {row['sim_keys']['world_seed']}\n", text)
        self.assertNotIn("room_margin_m", text)
        self.assertIn("room_margin_m", dropped)

    def test_key_changes_with_arguments_config_and_version(self):
        rows = suite_rows.tier_rows(DEFINITION, "quick", "/repo")
        r = rows[0]
        k = entry_key(r, "[sim]\n", "rgbdi-sim (rgbdi) 1.0", "c 1.0")
        self.assertEqual(k, entry_key(r, "[sim]\n", "rgbdi-sim (rgbdi) 1.0", "c 1.0"))
        self.assertNotEqual(k, entry_key(r, "[sim]\nx = 1\n", "rgbdi-sim (rgbdi) 1.0", "c 1.0"))
        self.assertNotEqual(k, entry_key(r, "[sim]\n", "rgbdi-sim (rgbdi) 1.1", "c 1.0"))
        self.assertNotEqual(k, entry_key(rows[1], "[sim]\n", "rgbdi-sim (rgbdi) 1.0", "c 1.0"))
        a = sim_arguments(r, "R.ini")
        self.assertEqual(a[:6], ["--profile", "handheld", "--seed", "1", "--fps", "15"])
        self.assertIn("--bag", a)
        self.assertEqual(a[-2:], ["--config", "R.ini"])


class CachePruning(unittest.TestCase):
    def test_least_recently_used_first_never_in_use_nor_incomplete(self):
        with tempfile.TemporaryDirectory() as d:
            def entry(name, size, mtime, complete=True):
                p = os.path.join(d, name)
                os.makedirs(p)
                with open(os.path.join(p, "sequence.rawlog"), "wb") as f:
                    f.write(b"x" * size)
                if complete:
                    open(os.path.join(p, "generation.json"), "w").close()
                os.utime(p, (mtime, mtime))
                return p
            entry("a", 100, 1000)
            b = entry("b", 100, 2000)
            entry("c", 100, 3000)
            entry("d", 100, 4000)
            entry("e.tmp1", 500, 500, complete=False)
            # 400 bytes of complete entries, cap 200: a (oldest) goes, b is in use, c goes
            self.assertEqual(prune_cache(d, 200, {b}), ["a", "c"])
            self.assertEqual(sorted(os.listdir(d)), ["b", "d", "e.tmp1"])
            self.assertEqual(prune_cache(d, 1000, set()), [])


class GenerationPeak(unittest.TestCase):
    def test_bag_rows_hold_three_copies_and_hybrid_rows_a_bound(self):
        import suite
        d = {"profiles": {"handheld": {"own_duration_s": 40}}}
        bag = {"duration_s": 30, "fps": 15, "layout": "bag", "profile": "handheld"}
        self.assertEqual(suite.generation_peak_bytes(d, bag), 30 * 15 * 1.5e6 * 3)
        files = {"duration_s": None, "fps": 30, "layout": "files", "profile": "handheld",
                 "speed_preset": None, "sim_keys": {}}
        self.assertEqual(suite.generation_peak_bytes(d, files), 40 * 30 * 0.5e6)
        hybrid = {"duration_s": None, "fps": 15, "layout": "bag", "profile": "recorded",
                  "speed_preset": None, "sim_keys": {}}
        self.assertEqual(suite.generation_peak_bytes(d, hybrid), 120 * 15 * 1.5e6 * 3)


class Journal(unittest.TestCase):
    SETUP = {"tier": "full", "only": None, "rows": ["a", "b", "c"]}

    def test_rows_and_sessions_survive_and_resume_skips_them(self):
        with tempfile.TemporaryDirectory() as d:
            j = suite_journal.Journal(d, self.SETUP, resume=False)
            j.record_generation("a", {"sim": {"wall_s": 10.0, "cpu_s": 9.0}})
            j.record_row({"id": "a", "status": "ok"})
            j.record_row({"id": "b", "status": "failed"})
            j.record_row({"id": "c", "status": "sequence generation failed: disk full"})
            j.record_session(100.0, 3)
            r = suite_journal.Journal(d, self.SETUP, resume=True)
            self.assertEqual(list(r.rows), ["a", "b"])
            self.assertEqual(r.rows["b"]["status"], "failed")
            self.assertEqual(r.generation, {"a": {"sim": {"wall_s": 10.0, "cpu_s": 9.0}}})
            self.assertEqual(r.sessions, [100.0])
            # without --resume the journal starts again
            self.assertEqual(suite_journal.Journal(d, self.SETUP, resume=False).rows, {})
            self.assertEqual(suite_journal.Journal(d, self.SETUP, resume=True).rows, {})

    def test_a_line_cut_by_a_kill_is_dropped_and_the_file_repaired(self):
        with tempfile.TemporaryDirectory() as d:
            j = suite_journal.Journal(d, self.SETUP, resume=False)
            j.record_row({"id": "a", "status": "ok"})
            with open(j.path, "a") as f:
                f.write('{"row": {"id": "b", "sta')
            r = suite_journal.Journal(d, self.SETUP, resume=True)
            self.assertEqual(list(r.rows), ["a"])
            r.record_row({"id": "b", "status": "ok"})
            self.assertEqual(list(suite_journal.Journal(d, self.SETUP, resume=True).rows),
                             ["a", "b"])

    def test_another_setup_is_refused_naming_what_differs(self):
        with tempfile.TemporaryDirectory() as d:
            suite_journal.Journal(d, self.SETUP, resume=False)
            other = dict(self.SETUP, tier="quick")
            with self.assertRaisesRegex(suite_journal.JournalError, r"another setup \(tier differ"):
                suite_journal.Journal(d, other, resume=True)
            with open(os.path.join(d, suite_journal.FILE_NAME), "w") as f:
                f.write('{"setup": {}}\nnot json\n{"session_wall_s": 1}\n')
            with self.assertRaisesRegex(suite_journal.JournalError, "line 2 is not JSON"):
                suite_journal.Journal(d, {}, resume=True)


class RunFigures(unittest.TestCase):
    TIME_V = ("\tUser time (seconds): 10.50\n\tSystem time (seconds): 1.50\n"
              "\tElapsed (wall clock) time (h:mm:ss or m:ss): 1:02.50\n"
              "\tMaximum resident set size (kbytes): 204800\n")

    def test_parse_time_v(self):
        self.assertEqual(suite_run.parse_time_v(self.TIME_V), (12.0, 62.5, 200.0))
        self.assertRaises(ValueError, suite_run.parse_time_v, "nothing")

    def test_metrics_and_failure_status(self):
        s = {"frames": 300, "stream_duration_s": 20.0, "resets": 1, "first_pose_time_s": 2.5,
             "keyframes": 60, "loop": {"accepted": 2},
             "evaluation": {"ate_rmse": 0.03, "coverage": 0.9},
             "evaluation_online": {"ate_rmse": 0.04}, "evaluation_odometry": {"ate_rmse": 0.05},
             "evaluation_sim3": {"scale": 0.98}}
        m = suite_run.metrics_from_summary(s, 12.0, 8.0, 200.0)
        self.assertEqual(m["status"], "ok")
        self.assertEqual((m["ate_odometry"], m["ate_online"], m["ate_final"]), (0.05, 0.04, 0.03))
        self.assertAlmostEqual(m["scale_error"], 0.02)
        self.assertEqual((m["cpu_per_data_s"], m["x_real_time"]), (0.6, 2.5))
        self.assertEqual((m["keyframes_per_frame"], m["loops_accepted"]), (0.2, 2))
        s["first_pose_time_s"] = None
        self.assertEqual(suite_run.metrics_from_summary(s, 1, 1, 1)["status"],
                         "never initialised")
        s["first_pose_time_s"] = 2.5
        del s["evaluation"]
        s["evaluation_error"] = "no pairs"
        self.assertEqual(suite_run.metrics_from_summary(s, 1, 1, 1)["status"],
                         "no evaluation: no pairs")
        # A build without loop closure: its one trajectory is the odometry (and online).
        old = {"frames": 300, "stream_duration_s": 20.0, "resets": 0, "first_pose_time_s": 2.5,
               "keyframes": 60, "evaluation": {"ate_rmse": 0.07, "coverage": 0.9}}
        m = suite_run.metrics_from_summary(old, 1, 1, 1)
        self.assertEqual((m["ate_odometry"], m["ate_online"], m["ate_final"]), (0.07, 0.07, 0.07))


if __name__ == "__main__":
    unittest.main()
